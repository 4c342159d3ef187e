"""corridorsim.files and corridorsim.analysis on hostile files (docs/analysis.md): bytes that are
not UTF-8, NaN and Infinity, numbers beyond a double, integers of thousands of digits, nesting
deep enough to exhaust Python's stack, missing columns. Each is refused with one InputError
naming the file (and the line where it is known), never another exception."""
import os

import pytest

from corridorsim.analysis import Run
from corridorsim.files import InputError

from test_analysis import write_run


def deep(n):
    return "[" * n + "]" * n


CASES = [
    ("metrics.json", b'{"pipelines": {"offset": {"note": "caf\xe9"}}}',
     r"metrics.json: cannot be read: 'utf-8' codec can't decode byte 0xe9"),
    ("metrics.json", b'{"pipelines": {"offset": {"ate_rmse_m": NaN}}}',
     r"metrics.json: invalid JSON: NaN is not JSON"),
    ("metrics.json", b'{"pipelines": {"offset": {"ate_rmse_m": -Infinity}}}',
     r"metrics.json: invalid JSON: -Infinity is not JSON"),
    ("metrics.json", b'{"pipelines": {"offset": {"ate_rmse_m": 1e999}}}',
     r"metrics.json: invalid JSON: 1e999 is not a finite number"),
    ("metrics.json", ('{"pipelines": {"offset": %s}}' % deep(5000)).encode(),
     r"metrics.json: invalid JSON: nested too deeply"),
    ("events.json", b'{"seed": 1, "duration_s": 1, "events": [{"t": 1, "t_ns": ' + b"9" * 5000 +
     b', "type": "slip"}]}', r"events.json: invalid JSON: Exceeds the limit"),
    ("events.json", b'{"seed": 1, "duration_s": 1e999, "events": []}',
     r"events.json: invalid JSON: 1e999 is not a finite number"),
    ("events.json", b'{"seed": 1, "duration_s": 1, "events": [{"t": 1, "t_ns": 1, '
     b'"type": "caf\xe9"}]}', r"events.json: cannot be read"),
    ("world.json", ('{"walls": %s}' % deep(5000)).encode(),
     r"world.json: invalid JSON: nested too deeply"),
    ("world.json", b'{"walls": [{"id": 1, "start": [NaN, -1.2], "end": [10, -1.2]}]}',
     r"world.json: invalid JSON: NaN is not JSON"),
    ("offset_errors.csv", b"t,ex_m\n0,1\n", r"offset_errors.csv:1: the header has no column"),
    ("offset_errors.csv", b"t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n"
     b"0,caf\xe9,0,0,0,0,0,0\n", r"offset_errors.csv: cannot be read"),
    ("offset_errors.csv", b"t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n"
     b"inf,0,0,0,0,0,0,0\n", r"offset_errors.csv:2: t: must be a finite time"),
    ("offset_nis.csv", b"t,type,dof,nis,accepted\n1.0,lamp,2,1e400,1\n",
     r"offset_nis.csv:2: nis: not finite"),
    ("offset.tum", b"0.1 0 0 0 0 0 0 1 # caf\xe9\n", r"offset.tum: cannot be read"),
    ("offset_landmarks.json", b'[{"id": 3, "type": "lamp", "status": "converged", '
     b'"label": "<!--<script>", "position_in_world": [1, 2, 2.5]}]',
     r"offset_landmarks.json:1: \[0\].covariance: expected 3 rows"),
    ("timing.json", b'{"sim_seconds": NaN}', r"timing.json: invalid JSON: NaN is not JSON"),
]


@pytest.mark.parametrize("name,data,message", CASES,
                         ids=[f"{i:02d}-{case[0]}" for i, case in enumerate(CASES)])
def test_hostile_files_are_refused_naming_the_file(tmp_path, name, data, message):
    write_run(str(tmp_path))
    with open(os.path.join(tmp_path, name), "wb") as f:
        f.write(data)
    with pytest.raises(InputError, match=message):
        run = Run(str(tmp_path))
        run.events  # noqa: B018
        run.world  # noqa: B018
        run.timing  # noqa: B018
        run.trajectory("offset")
        run.errors("offset")
        run.nis("offset")
        run.landmarks("offset")
        run.ate("offset")
