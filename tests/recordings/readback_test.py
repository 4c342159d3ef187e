#!/usr/bin/python3
"""recording.readback: a run of every kind of sensor (scenarios/rigs.yaml: the front RGB-D and
lateral cameras, an IMU, a laser scanner, four pipelines) recorded with --record and exported
with --export, its recording read back by @mcap/core and @foxglove/rosmsg2-serialization
(read_mcap.mjs, the summary's index and a CRC-checking stream read), every message compared with
the run folder's files and the export's images (check_readback.py). Then the same run with lz4
and without compression reads back the same messages.

Usage: readback_test.py CORRIDORSIM NODE SOURCE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys


def run(argv, **kw):
    result = subprocess.run(argv, capture_output=True, text=True, **kw)
    if result.returncode not in (0, 3):
        sys.exit("readback_test: %s exited %d:\n%s%s" % (" ".join(argv), result.returncode,
                                                         result.stdout[-3000:], result.stderr[-3000:]))
    return result


def main():
    corridorsim, node, source, work = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    here = os.path.dirname(os.path.abspath(__file__))
    outputs = {}
    for compression in ("zstd", "lz4", "none"):
        out = os.path.join(work, "run_" + compression)
        argv = [corridorsim, "run", os.path.join(source, "scenarios", "rigs.yaml"), "--set",
                "duration_s=3", "--record", "--record-compression", compression, "--no-plots",
                "--no-viewer", "--out", out]
        if compression == "zstd":
            argv += ["--export", os.path.join(work, "export")]
        run(argv)
        jsonl = os.path.join(work, compression + ".jsonl")
        with open(jsonl, "w") as f:
            result = subprocess.run([node, os.path.join(here, "read_mcap.mjs"),
                                     os.path.join(out, "recording.mcap")], stdout=f,
                                    stderr=subprocess.PIPE, text=True)
        if result.returncode != 0:
            sys.exit("readback_test: read_mcap.mjs failed on %s:\n%s" % (compression, result.stderr))
        outputs[compression] = jsonl
    check = [sys.executable, os.path.join(here, "check_readback.py"), outputs["zstd"],
             os.path.join(work, "run_zstd"), os.path.join(work, "export")]
    print(run(check).stdout, end="")
    with open(outputs["zstd"]) as f:
        reference = [l for l in f if not l.startswith('{"summary"')]
    for compression in ("lz4", "none"):
        with open(outputs[compression]) as f:
            lines = [l for l in f if not l.startswith('{"summary"')]
        if lines != reference:
            sys.exit("readback_test: the %s recording reads back other messages than zstd's" % compression)
    # The recording does not depend on the compression beyond its chunks: same messages, and a
    # recording's bytes do not depend on the run's timing (two runs, same bytes).
    again = os.path.join(work, "run_again")
    run([corridorsim, "run", os.path.join(source, "scenarios", "rigs.yaml"), "--set", "duration_s=3",
         "--record", "--record-compression", "lz4", "--no-plots", "--no-viewer", "--out", again])
    with open(os.path.join(work, "run_lz4", "recording.mcap"), "rb") as a, \
            open(os.path.join(again, "recording.mcap"), "rb") as b:
        if a.read() != b.read():
            sys.exit("readback_test: two runs of one scenario and seed wrote different recordings")
    print("readback_test: ok (zstd, lz4 and none read back the same messages; recordings are "
          "byte-identical run to run)")


if __name__ == "__main__":
    main()
