"""How the scripts find what they import (standard library only). Debian's python3-matplotlib,
python3-numpy and python3-pandas live in /usr/bin/python3's site-packages; a pyenv or venv
`python3` that comes first on PATH may not see them, so a script that misses one re-runs itself
there, once. The corridorsim package is the installed one, else the checkout's python/ folder
beside scripts/."""

import importlib
import os
import sys

SYSTEM_PYTHON = "/usr/bin/python3"
# The environment variable that marks the second start of a plot script (plot_run.py,
# plot_study.py) under SYSTEM_PYTHON, and the package that brings matplotlib.
PLOT_REEXEC_ENV = "CORRIDORSIM_PLOT_REEXEC"
PLOT_HINT = "scripts/setup.sh installs python3-matplotlib"


def rerun_or_exit(script, missing, program, reexec_env=PLOT_REEXEC_ENV, hint=PLOT_HINT,
                  status=1):
    """After `missing` (the ImportError of a module `script` needs): re-runs `script` under
    SYSTEM_PYTHON with the same arguments when that is another python3 and this is not already
    the second start (`reexec_env` set); else prints `<program>: <module> is not installed for
    <python> (<hint>)` and exits with `status`."""
    if (not os.environ.get(reexec_env) and os.path.exists(SYSTEM_PYTHON) and
            os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON)):
        os.environ[reexec_env] = "1"
        os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(script)] + sys.argv[1:])
    print(f"{program}: {missing.name} is not installed for {sys.executable} ({hint})",
          file=sys.stderr)
    sys.exit(status)


def use_corridorsim_with(*modules):
    """Makes `import corridorsim.<module>` work for each of `modules`: the installed package when
    it has them, else the checkout's python/ folder beside scripts/ (an installed package without
    one is forgotten, so that the checkout's is imported whole)."""
    try:
        for module in modules:
            importlib.import_module("corridorsim." + module)
    except ImportError:
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..",
                                        "python"))
        for name in [m for m in sys.modules if m == "corridorsim" or m.startswith("corridorsim.")]:
            del sys.modules[name]
