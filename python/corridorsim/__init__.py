"""corridorsim for Python: the reference client of the lockstep protocol (docs/protocol.md).

A pipeline that is a program::

    import corridorsim

    class DeadReckoning(corridorsim.Pipeline):
        def on_start(self, calibration, start): ...
        def on_odometry(self, odometry): ...
        def estimate(self): return corridorsim.Estimate(pose, covariance)

    if __name__ == "__main__":
        corridorsim.serve(DeadReckoning)
"""

from .pipeline import (Calibration, CameraCalibration, CameraFrame, Estimate, Odometry, Pipeline,
                       Start, serve)
from .protocol import PROTOCOL_VERSION, Connection, ProtocolError

__all__ = ["Calibration", "CameraCalibration", "CameraFrame", "Connection", "Estimate",
           "Odometry", "PROTOCOL_VERSION", "Pipeline", "ProtocolError", "Start", "serve"]
