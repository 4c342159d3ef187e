"""What the Python CLI tests (tests/harness/cli_*_test.py) share: the options that leave out the
extras, a failure that ends the test, a fresh work folder, corridorsim run with an expected exit
code, a file's bytes.

Import it from a test beside it:
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from cli_test_support import NO_EXTRAS, fail, fresh_folder, read, run  # noqa: E402
"""

import os
import shutil
import subprocess
import sys

# What these runs and studies check is their results: plots/ and the pages are left out
# (scripts.plot_run, viewer.browser and viewer.odd_data test those).
NO_EXTRAS = ["--no-plots", "--no-viewer"]


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def fresh_folder(path):
    """`path` emptied (made when missing): a test's work folder from a previous run is gone."""
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def run(binary, args, expect, cwd):
    result = subprocess.run([binary] + args, cwd=cwd, capture_output=True, text=True)
    if result.returncode != expect:
        fail("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" % (
            " ".join(args), result.returncode, expect, result.stdout[-3000:], result.stderr))
    return result


def read(path):
    with open(path, "rb") as f:
        return f.read()
