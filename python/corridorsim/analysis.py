"""corridorsim's outputs for notebooks and scripts: a run folder (`Run`), a study folder (`Study`)
and a dataset (`Dataset`, in corridorsim.dataset) as pandas DataFrames (docs/analysis.md).

    import corridorsim
    run = corridorsim.Run("out/run")
    run.ate("p3_upward") == run.metrics["pipelines"]["p3_upward"]["ate_rmse_m"]   # True

Every file is read through corridorsim.files' strict readers: a missing or malformed file raises
files.InputError naming the file and, where it can, the line. Files are read when first asked
for and kept.

Exactness. metrics.json's trajectory metrics are computed by the runner from the poses as the
run's TUM files hold them (harness/metrics/trajectory.h PoseAsWritten). `Run.trajectory_metrics`
repeats the runner's arithmetic operation by operation in Python floats (IEEE doubles, sequential
sums, the same libm functions) and rounds as the runner does, so `Run.ate`, `Run.rpe` and
`Run.final_error` equal metrics.json's numbers, float for float (scripts/check_analysis.py checks
every pipeline of every shipped scenario).

Units: metres, seconds, radians; world frame W (docs/frames.md).
"""

# The analysis side lives in one module per folder kind; its names are importable from here
# (docs/analysis.md): run.py (Run), study.py (Study), dataset.py (Dataset), trajectory_metrics.py
# (the runner's arithmetic).
from .dataset import Dataset
from .files import InputError
from .run import MAX_SCENARIO_BYTES, Run  # noqa: F401
from .study import Study
from .trajectory_metrics import (RPE_DISTANCES_M, STEPS_PER_METRE, STEPS_PER_RAD,  # noqa: F401
                                 TWO_PI, match_to_truth, normalize_angle, round_to_step,
                                 trajectory_metrics, yaw_from_quaternion)

__all__ = ["Run", "Study", "Dataset", "InputError", "normalize_angle", "round_to_step",
           "yaw_from_quaternion", "RPE_DISTANCES_M"]
