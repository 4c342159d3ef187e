#!/usr/bin/python3
"""corridorsim as a team installs it (docs/install.md, docs/plugins.md): `cmake --install` into a
temporary prefix, the example plugin copied from the installed docs and built out of tree against
that prefix with find_package, then run, test --junit (the 4-seed study), study (2 workers; 2
shards merged byte-identical to the whole) and `corridorsim plugin`, each checked from outside; and
the Debian packages `cpack` makes from the build tree: file lists, Depends, and the program run
from a root they are unpacked into.

usage: install_and_plugin_test.py BUILD_DIR WORK_DIR [--no-deb]
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

# What these runs and studies check is their results: plots/ and the pages are left out
# (scripts.plot_run, viewer.browser and viewer.odd_data test those).
NO_EXTRAS = ["--no-plots", "--no-viewer"]


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def run(args, expect=0, cwd=None, env=None):
    print("+ " + " ".join(args), flush=True)
    start = time.monotonic()
    p = subprocess.run(args, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    # Each step's time, for the CI budget (docs/ci.md).
    print("  (%.1f s)" % (time.monotonic() - start), flush=True)
    if p.returncode != expect:
        fail("%s exited %d (expected %d)\nstdout:\n%s\nstderr:\n%s" %
             (" ".join(args), p.returncode, expect, p.stdout[-3000:], p.stderr[-3000:]))
    return p


def read(path, mode="r"):
    with open(path, mode) as f:
        return f.read()


def cache_value(build_dir, name):
    for line in read(os.path.join(build_dir, "CMakeCache.txt")).splitlines():
        if line.split(":", 1)[0] == name:
            return line.split("=", 1)[1]
    fail("%s/CMakeCache.txt has no %s" % (build_dir, name))


def eigen_only_plugin(prefix, corridorsim, work, env):
    """tests/plugins/echo_plugin.cpp (Eigen and the SDK only) built against the prefix with
    OpenCV's and OctoMap's CMake packages disabled: once with their headers and libraries where
    Debian's component packages put them (libopencv-core-dev, libopencv-ml-dev, liboctomap-dev:
    what corridorsim-dev depends on), where a source that includes the SDK's OpenCV and OctoMap
    headers builds too; once with those hidden from every find_* (a prefix without them), where
    the Eigen-only plugin still builds and loads."""
    source = os.path.join(work, "eigen_only")
    os.makedirs(source)
    shutil.copy(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plugins",
                             "echo_plugin.cpp"), source)
    with open(os.path.join(source, "uses_opencv.cpp"), "w") as f:
        f.write('#include "slam/features/door_plates.h"\n'
                '#include "slam/mapping/occupancy_mapper.h"\n'
                'int UsesOpenCv() { return cv::Mat(2, 3, CV_8U, cv::Scalar(1)).rows; }\n')
    with open(os.path.join(source, "CMakeLists.txt"), "w") as f:
        f.write("cmake_minimum_required(VERSION 3.25)\n"
                "project(eigen_only_plugin LANGUAGES CXX)\n"
                "find_package(corridorsim 0.3 CONFIG REQUIRED)\n"
                "corridorsim_add_pipeline_plugin(eigen_only SOURCES echo_plugin.cpp)\n"
                "if(WITH_OPENCV_HEADERS)\n"
                "  corridorsim_add_pipeline_plugin(with_opencv SOURCES uses_opencv.cpp)\n"
                "endif()\n")
    disabled = ["-DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON", "-DCMAKE_DISABLE_FIND_PACKAGE_octomap=ON"]
    # The folders the files lie in, under both names of a merged /usr.
    hidden = set()
    for name in ["opencv4/opencv2/core.hpp", "octomap/OcTree.h"]:
        for include in ["/usr/include", "/usr/local/include"]:
            if os.path.exists(os.path.join(include, name)):
                hidden.update([include, os.path.join(include, name.split("/")[0])])
    for lib in ["libopencv_core.so", "libopencv_ml.so", "liboctomap.so", "liboctomath.so"]:
        for folder in ["/usr/lib/x86_64-linux-gnu", "/usr/lib", "/usr/local/lib"]:
            if os.path.exists(os.path.join(folder, lib)):
                hidden.update([folder, "/" + os.path.relpath(folder, "/usr")])
    for case, extra in [("components", ["-DWITH_OPENCV_HEADERS=ON"]),
                        ("stripped", ["-DCMAKE_IGNORE_PATH=" + ";".join(sorted(hidden))])]:
        build = os.path.join(source, "build_" + case)
        run(["cmake", "-S", source, "-B", build, "-G", "Ninja", "-DCMAKE_PREFIX_PATH=" + prefix,
             "-DCMAKE_BUILD_TYPE=Release", *disabled, *extra])
        found = cache_value(build, "corridorsim_OPENCV_INCLUDE_DIR")
        if (case == "stripped") != found.endswith("NOTFOUND"):
            fail("%s: corridorsim's package found OpenCV's headers at %r" % (case, found))
        run(["cmake", "--build", build])
        described = run([corridorsim, "plugin", os.path.join(build, "eigen_only.so")],
                        env=env).stdout
        if "## pipeline type `test_echo`" not in described:
            fail("%s: the Eigen-only plugin does not load:\n%s" % (case, described))


def main():
    if len(sys.argv) < 3:
        fail(__doc__)
    build = os.path.abspath(sys.argv[1])
    work = os.path.abspath(sys.argv[2])
    with_deb = "--no-deb" not in sys.argv[3:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    # The installed program must not need the build tree's environment.
    env = {k: v for k, v in os.environ.items() if k != "CORRIDORSIM_DATA_DIR"}

    # 1. cmake --install into a prefix: what is there, and what is not.
    prefix = os.path.join(work, "prefix")
    run(["cmake", "--install", build, "--prefix", prefix])
    for rel in ["bin/corridorsim", "lib/libcorridorsim_common.so.3", "lib/libcorridorsim_slam.so.3",
                "include/corridorsim/slam/pipeline.h", "include/corridorsim/slam/plugin.h",
                "include/corridorsim/slam/sdk_version.h", "include/corridorsim/common/pose.h",
                "include/corridorsim/slam/ekf/ekf_state.h",
                "lib/cmake/corridorsim/corridorsimConfig.cmake",
                "lib/cmake/corridorsim/corridorsimConfigVersion.cmake",
                "share/corridorsim/scenarios/default.yaml",
                "share/corridorsim/scenarios/studies/p1_fig15.yaml",
                "share/corridorsim/models/door_plate_svm.yml",
                "share/corridorsim/scripts/plot_run.py",
                "share/corridorsim/scripts/plot_evaluation.py", "share/doc/corridorsim/plugins.md",
                "share/corridorsim/scripts/make_viewer.py", "share/corridorsim/scripts/make_report.py",
                "share/corridorsim/scripts/system_python.py", "share/corridorsim/scripts/pages.py",
                "share/corridorsim/scripts/plot_plan.py", "share/corridorsim/scripts/plot_map.py",
                "share/corridorsim/scripts/plot_detections.py",
                "share/corridorsim/scripts/study_summary.py",
                "share/corridorsim/viewer/viewer.js", "share/corridorsim/viewer/report.js",
                "share/corridorsim/viewer/page.js", "share/corridorsim/viewer/viewer_plan.js",
                "share/corridorsim/viewer/viewer_plots.js",
                "share/corridorsim/viewer/viewer_frames.js",
                "share/corridorsim/viewer/viewer_tables.js",
                "share/corridorsim/viewer/page_head.html",
                "share/corridorsim/viewer/page_header.html",
                "share/corridorsim/viewer/page_tail.html",
                "share/corridorsim/viewer/vendor/uplot/uPlot.iife.min.js",
                "lib/python3/dist-packages/corridorsim/files.py",
                "lib/python3/dist-packages/corridorsim/analysis.py",
                "lib/python3/dist-packages/corridorsim/readers.py",
                "lib/python3/dist-packages/corridorsim/run.py",
                "share/doc/corridorsim/examples/cpp_plugin/lamp_ekf.cpp"]:
        if not os.path.exists(os.path.join(prefix, rel)):
            fail("cmake --install did not install " + rel)
    for rel in ["include/corridorsim/harness", "include/corridorsim/sim",
                "include/corridorsim/render", "include/corridorsim/worlds",
                "include/corridorsim/common/io"]:
        if os.path.exists(os.path.join(prefix, rel)):
            fail("an internal folder is installed: " + rel)
    corridorsim = os.path.join(prefix, "bin", "corridorsim")

    # 2. The installed program finds its data beside itself, from an empty folder.
    empty = os.path.join(work, "empty")
    os.makedirs(empty)
    version = run([corridorsim, "--version"], cwd=empty, env=env).stdout
    if not version.startswith("corridorsim ") or "SDK ABI version" not in version:
        fail("--version printed: " + version)
    data = os.path.join(prefix, "share", "corridorsim")
    if ("data " + os.path.realpath(data)) not in version:
        fail("the installed program's data folder is not %s: %s" % (data, version))
    p = run([corridorsim, "world", "--out", "w"], cwd=empty, env=env)
    if os.path.join(os.path.realpath(data), "scenarios", "default.yaml") not in p.stderr:
        fail("`corridorsim world` from an empty folder did not use the installed default.yaml: " +
             p.stderr)

    # 3. The example, copied from the installed docs, built against the prefix alone.
    example = os.path.join(work, "example")
    shutil.copytree(os.path.join(prefix, "share/doc/corridorsim/examples/cpp_plugin"), example)
    # Ninja: what scripts/setup.sh installs (a fresh machine may lack make).
    run(["cmake", "-S", example, "-B", os.path.join(example, "build"), "-G", "Ninja",
         "-DCMAKE_PREFIX_PATH=" + prefix, "-DCMAKE_BUILD_TYPE=Release"])
    run(["cmake", "--build", os.path.join(example, "build")])
    library = os.path.join(example, "build", "lamp_ekf.so")
    described = run([corridorsim, "plugin", library], env=env).stdout
    for part in ["plugin lamp_ekf_example 1.0.0", "## pipeline type `lamp_ekf`",
                 "| `ceiling_height_m` | m | 2.7 | [0.5, 20] |"]:
        if part not in described:
            fail("`corridorsim plugin` does not print %r:\n%s" % (part, described))
    scenario = os.path.join(example, "lamp_ekf.yaml")

    # 3b. A plugin that uses Eigen alone needs neither OpenCV's nor OctoMap's CMake package (Debian
    # 12: libopencv-dev, which pulls Qt 5 and VTK, alone has OpenCVConfig.cmake), and not even
    # their files: corridorsim's package finds those from their files, for the headers that
    # include them.
    eigen_only_plugin(prefix, corridorsim, work, env)

    # 4. run: the plugin beats dead reckoning; provenance records the library.
    run_dir = os.path.join(work, "run")
    run([corridorsim, "run", scenario, "--out", run_dir], env=env)
    metrics = json.loads(read(os.path.join(run_dir, "metrics.json")))["pipelines"]
    mine, odometry = metrics["lamp_ekf"]["ate_rmse_m"], metrics["odometry"]["ate_rmse_m"]
    print("run: lamp_ekf ATE %.4f m, odometry %.4f m" % (mine, odometry))
    if not mine < 0.5 * odometry:
        fail("lamp_ekf's ATE %.4f is not below half of odometry's %.4f" % (mine, odometry))
    if not os.path.exists(os.path.join(run_dir, "plots", "summary.png")):
        fail("the installed program wrote no plots")
    # viewer.html from the installed page sources and uPlot, nothing of the checkout.
    page = read(os.path.join(run_dir, "viewer.html"))
    if "corridorsim-data" not in page or "uPlot" not in page:
        fail("the installed program wrote no viewer.html with its data and uPlot")
    plugins = json.loads(read(os.path.join(run_dir, "provenance.json")))["plugins"]
    digest = hashlib.sha256(read(library, "rb")).hexdigest()
    if len(plugins) != 1 or plugins[0]["sha256"] != digest or plugins[0]["version"] != "1.0.0" \
            or plugins[0]["path"] != os.path.realpath(library):
        fail("provenance.json plugins: %s (the library's sha256 is %s)" % (plugins, digest))

    # The installed `evaluate` (and its plot script, which imports plot_run.py beside it) on the
    # plugin's own trajectory: metrics.json's ATE.
    evaluation_dir = os.path.join(work, "evaluation")
    run([corridorsim, "evaluate", run_dir, "--estimate",
         "lamp_ekf=%s" % os.path.join(run_dir, "lamp_ekf.tum"), "--out", evaluation_dir],
        cwd=empty, env=env)
    evaluated = json.loads(read(os.path.join(evaluation_dir, "evaluation.json")))
    if abs(evaluated["estimates"]["lamp_ekf"]["ate_rmse_m"] - mine) > 3e-6 or \
            not os.path.exists(os.path.join(evaluation_dir, "plots", "trajectories.png")):
        fail("installed evaluate: ATE %s against metrics.json's %s, plots %s" % (
            evaluated["estimates"]["lamp_ekf"]["ate_rmse_m"], mine,
            os.listdir(evaluation_dir)))

    # 5. test --junit runs the example's 4-seed study: a JUnit reader parses the report, nothing
    # failed, and the study's expectations (lamp_ekf beats odometry) passed.
    junit = os.path.join(work, "junit.xml")
    run([corridorsim, "test", scenario, "--junit", junit, "--out", os.path.join(work, "test")],
        env=env)
    suites = ET.parse(junit).getroot()
    cases = suites.findall(".//testcase")
    failed = [c.get("name") for c in cases if c.find("failure") is not None or
              c.find("error") is not None]
    if not cases or failed:
        fail("junit.xml: %d cases, failed: %s" % (len(cases), failed))
    summary = json.loads(read(os.path.join(work, "test", "000_lamp_ekf", "summary.json")))
    expectations = summary["points"][0]["expectations"]
    print("study: %s" % json.dumps(expectations))
    point = summary["points"][0]
    if point["runs"]["finished"] != 4 or not summary["all_expectations_passed"] or \
            len(expectations) != 2:
        fail("the study's runs and expectations (lamp_ekf beats odometry): %s" % point)

    # 6. The study with 2 workers, and the same study in 2 shards merged: byte-identical summaries.
    # Two of its seeds (--runs 2), each run cut to its first 30 s (--set duration_s=30), are
    # enough for that: every run and the merge are the same code for any count and length, and
    # step 5 ran all four whole.
    whole = os.path.join(work, "study")
    short = ["--set", "duration_s=30"]
    run([corridorsim, "study", scenario, "--runs", "2", "--jobs", "2", *short, *NO_EXTRAS,
         "--out", whole], env=env)
    for k in (1, 2):
        run([corridorsim, "study", scenario, "--runs", "2", "--shard", "%d/2" % k, "--jobs", "1",
             *short, *NO_EXTRAS, "--out", os.path.join(work, "part%d" % k)], env=env)
    merged = os.path.join(work, "merged")
    run([corridorsim, "study", "merge", os.path.join(work, "part1"), os.path.join(work, "part2"),
         *NO_EXTRAS, "--out", merged], env=env)
    for name in ["summary.json", "summary.csv", "paired.csv"]:
        if read(os.path.join(whole, name), "rb") != read(os.path.join(merged, name), "rb"):
            fail("%s of the merged shards differs from the whole study's" % name)
    if json.loads(read(os.path.join(whole, "summary.json")))["points"][0]["runs"]["finished"] != 2:
        fail("the 2-worker study did not run 2 seeds")

    if not with_deb:
        return
    # 7. The Debian packages, from the build tree.
    debs = os.path.join(work, "deb")
    run(["cpack", "--config", os.path.join(build, "CPackConfig.cmake"), "-B", debs])
    from_cmake = read(os.path.join(build, "CMakeCache.txt"))
    version = [l.split("=", 1)[1] for l in from_cmake.splitlines()
               if l.startswith("CMAKE_PROJECT_VERSION:")][0]
    runtime = os.path.join(debs, "corridorsim_%s_amd64.deb" % version)
    dev = os.path.join(debs, "corridorsim-dev_%s_amd64.deb" % version)
    for deb in (runtime, dev):
        if not os.path.exists(deb):
            fail("cpack made no %s (made: %s)" % (deb, os.listdir(debs)))
    depends = run(["dpkg-deb", "-f", runtime, "Depends"]).stdout
    for package in ["libopencv-core4", "libc6", "libstdc++6", "python3-matplotlib",
                    "liboctomap1.9"]:
        if package not in depends:
            fail("the runtime package's Depends lacks %s: %s" % (package, depends))
    dev_depends = run(["dpkg-deb", "-f", dev, "Depends"]).stdout
    # The -dev packages of the headers the SDK's headers include, not libopencv-dev (every OpenCV
    # module, Qt 5, VTK).
    print("Depends: corridorsim: %s  corridorsim-dev: %s" % (depends.strip(), dev_depends.strip()))
    for package in ["corridorsim (= %s)" % version, "libeigen3-dev", "libopencv-core-dev",
                    "libopencv-ml-dev", "liboctomap-dev"]:
        if package not in dev_depends:
            fail("the dev package's Depends lacks %s: %s" % (package, dev_depends))
    if "libopencv-dev" in dev_depends or "-dev" in depends:
        fail("a package depends on more -dev packages than the SDK's headers include: %s / %s"
             % (depends, dev_depends))
    files = run(["dpkg-deb", "-c", runtime]).stdout
    for rel in ["./usr/bin/corridorsim", "./usr/share/corridorsim/scenarios/default.yaml",
                "./usr/share/corridorsim/models/room_number_mlp.yml",
                "./usr/share/corridorsim/scripts/plot_study.py",
                "./usr/share/corridorsim/scripts/study_summary.py",
                "./usr/share/corridorsim/scripts/system_python.py",
                "./usr/share/corridorsim/viewer/page.js",
                "./usr/share/corridorsim/viewer/viewer_plan.js"]:
        if rel not in files:
            fail("the runtime package lacks " + rel)
    if "./usr/include/" in files:
        fail("the runtime package holds headers (they belong in corridorsim-dev)")
    dev_files = run(["dpkg-deb", "-c", dev]).stdout
    for rel in ["./usr/include/corridorsim/slam/plugin.h",
                "./usr/lib/cmake/corridorsim/corridorsimConfig.cmake"]:
        if rel not in dev_files:
            fail("the dev package lacks " + rel)
    # Unpacked into a root of its own (CI cannot install system-wide), it runs and finds its data.
    root = os.path.join(work, "root")
    run(["dpkg-deb", "-x", runtime, root])
    version_text = run([os.path.join(root, "usr/bin/corridorsim"), "--version"], cwd=empty,
                       env=env).stdout
    if "data " + os.path.realpath(os.path.join(root, "usr/share/corridorsim")) not in version_text:
        fail("the unpacked package's program does not find its data: " + version_text)


if __name__ == "__main__":
    main()
    print("install_and_plugin_test: ok")
