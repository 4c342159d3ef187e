"""corridorsim for Python: the reference client of the lockstep protocol (docs/protocol.md).

A pipeline that is a program::

    import corridorsim

    class DeadReckoning(corridorsim.Pipeline):
        def on_start(self, calibration, start): ...
        def on_odometry(self, odometry): ...
        def estimate(self): return corridorsim.Estimate(pose, covariance)

    if __name__ == "__main__":
        corridorsim.serve(DeadReckoning)

The analysis side (docs/analysis.md): `corridorsim.Run(path)`, `corridorsim.Study(path)` and
`corridorsim.Dataset(path)` read a run folder, a study folder and a dataset into pandas
DataFrames. They live in corridorsim.analysis, imported on first use, so `import corridorsim`
stays light (no numpy or pandas) for pipelines that only need the protocol client; the strict
readers they use are in corridorsim.files.
"""

from .pipeline import (Calibration, CameraCalibration, CameraFrame, Estimate, ImuCalibration,
                       ImuSample, LaserCalibration, LaserScan, Odometry, Pipeline, Start, serve)
from .protocol import PROTOCOL_VERSION, Connection, ProtocolError

__all__ = ["Calibration", "CameraCalibration", "CameraFrame", "Connection", "Dataset", "Estimate",
           "ImuCalibration", "ImuSample", "LaserCalibration", "LaserScan", "Odometry",
           "PROTOCOL_VERSION", "Pipeline", "ProtocolError", "Run", "Start", "Study", "serve"]

_ANALYSIS_NAMES = ("Run", "Study", "Dataset")


def __getattr__(name):
    """Run, Study and Dataset: imports corridorsim.analysis (numpy, pandas) on first use."""
    if name in _ANALYSIS_NAMES:
        from . import analysis
        value = getattr(analysis, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_ANALYSIS_NAMES))
