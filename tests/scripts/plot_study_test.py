#!/usr/bin/env python3
"""scripts/plot_study.py on a real study (`corridorsim study`, a short camera-less sweep of two
points and two pipelines): every plot is written as a PNG, the same bytes twice; a broken
summary.json exits 2 naming the file, and leaves no plot.

Usage: plot_study_test.py CORRIDORSIM SOURCE_DIR WORK_DIR (run with a python3 that imports
matplotlib)."""
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


def main():
    binary, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    study = os.path.join(work, "s.yaml")
    with open(study, "w") as f:
        f.write("include: %s\nduration_s: 8\npipelines:\n  second:\n    type: odometry\n"
                "study:\n  runs: 3\n  vary:\n    robot.odometry.random_k_m: [1.0e-5, 1.0e-3]\n"
                % os.path.join(source, "scenarios", "umbmark_cw.yaml"))
    done = subprocess.run([binary, "study", study, "--out", os.path.join(work, "st"),
                           *NO_EXTRAS], capture_output=True, text=True)
    if done.returncode != 0:
        fail("study exited %d: %s" % (done.returncode, done.stderr))
    script = os.path.join(source, "scripts", "plot_study.py")
    names = ["ate_box.png", "error_over_time.png", "error_axes.png", "nees.png", "sweep.png"]
    images = []
    for _ in range(2):
        done = subprocess.run([sys.executable, script, os.path.join(work, "st")],
                              capture_output=True, text=True)
        if done.returncode != 0:
            fail("plot_study.py exited %d: %s" % (done.returncode, done.stderr))
        pngs = []
        for name in names:
            path = os.path.join(work, "st", "plots", name)
            with open(path, "rb") as f:
                data = f.read()
            if not data.startswith(b"\x89PNG\r\n\x1a\n") or len(data) < 5000:
                fail("%s is not a drawn PNG" % name)
            pngs.append(data)
        images.append(pngs)
    if images[0] != images[1]:
        fail("the plots are not the same bytes twice")

    # frame_times.csv (P1's pipelines write frame costs; written here by hand) adds its plot; a
    # malformed one is bad input.
    frame_times = os.path.join(work, "st", "frame_times.csv")
    with open(frame_times, "w") as f:
        f.write("point,pipeline,landmarks_low,landmarks_high,frames,mean_ms,median_ms,p95_ms\n"
                "p000,odometry,0,9,10,1.5,1.2,3.0\np000,odometry,10,19,12,2.5,2.2,4.0\n")
    done = subprocess.run([sys.executable, script, os.path.join(work, "st")],
                          capture_output=True, text=True)
    if done.returncode != 0 or "frame_times.png" not in done.stdout:
        fail("frame_times.csv: exit %d, %s %s" % (done.returncode, done.stdout, done.stderr))
    with open(frame_times, "a") as f:
        f.write("p000,odometry,20,29,x,1,1,1\n")
    done = subprocess.run([sys.executable, script, os.path.join(work, "st")],
                          capture_output=True, text=True)
    if done.returncode != 2 or "frame_times.csv: line 4" not in done.stderr:
        fail("malformed frame_times.csv: exit %d, %s" % (done.returncode, done.stderr))

    broken = os.path.join(work, "broken")
    os.makedirs(broken)
    with open(os.path.join(broken, "summary.json"), "w") as f:
        f.write('{"schema_version": 1, "points": [{"id": 3}]}')
    done = subprocess.run([sys.executable, script, broken], capture_output=True, text=True)
    if done.returncode != 2 or "summary.json" not in done.stderr or "Traceback" in done.stderr:
        fail("broken summary: exit %d, %s" % (done.returncode, done.stderr))
    if os.path.exists(os.path.join(broken, "plots")) and os.listdir(os.path.join(broken, "plots")):
        fail("plots written for a broken summary")
    print("PASS")


if __name__ == "__main__":
    main()
