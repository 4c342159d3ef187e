#!/usr/bin/python3
"""scripts/check_node_engines.js, which scripts/setup.sh runs before `npm ci` in viewer/:

  - the shipped viewer/package-lock.json runs on Debian 12's Node.js (18.20.4) and this node;
  - a lockfile whose package needs a newer Node fails (exit 1) with one line naming the
    lockfile, the package, its version and range, and the Node version;
  - npm's range forms (>=, >, <, <=, ^, ~, x, hyphen, ||, spaces) read as npm reads them;
  - a range it cannot read, a missing lockfile or a bad version exit 2 naming it.

    check_node_engines_test.py NODE SOURCE_DIR WORK_DIR
"""

import json
import os
import shutil
import subprocess
import sys

DEBIAN_12_NODE = "18.20.4"


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def main():
    node, source, work = sys.argv[1:4]
    script = os.path.join(source, "scripts", "check_node_engines.js")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    def check(lock, version=None):
        argv = [node, script, lock] + ([version] if version else [])
        p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           timeout=60)
        return p.returncode, p.stdout

    def lockfile(name, engines):
        path = os.path.join(work, name)
        packages = {"": {"name": "x", "version": "1.0.0"}}
        for i, rng in enumerate(engines):
            packages[f"node_modules/pkg{i}"] = {"version": f"{i}.1.0", "engines": {"node": rng}}
        with open(path, "w", encoding="utf-8") as f:
            json.dump({"name": "x", "lockfileVersion": 3, "packages": packages}, f)
        return path

    shipped = os.path.join(source, "viewer", "package-lock.json")
    for version in (DEBIAN_12_NODE, None):
        rc, out = check(shipped, version)
        if rc != 0:
            fail(f"viewer/package-lock.json on Node {version or 'of this machine'}: exit {rc}: {out}")

    too_new = lockfile("too_new.json", [">=18", ">=20"])
    rc, out = check(too_new, DEBIAN_12_NODE)
    lines = out.strip().splitlines()
    if rc != 1 or len(lines) != 1:
        fail(f"a package needing Node >=20 on {DEBIAN_12_NODE}: exit {rc}, output {out!r}")
    for part in (too_new, "pkg1 1.1.0", ">=20", DEBIAN_12_NODE):
        if part not in lines[0]:
            fail(f"the message {lines[0]!r} does not name {part!r}")

    cases = [  # (range, version, satisfied)
        (">=18", "18.0.0", True), (">=18", "17.9.9", False), (">=18.17.0", "18.16.1", False),
        (">18", "18.20.4", False), (">18", "19.0.0", True), (">18.2.0", "18.2.1", True),
        ("<20", "19.99.0", True), ("<20", "20.0.0", False), ("<=18", "18.20.4", True),
        ("<=18.2", "18.3.0", False), ("^18.17.0", "18.20.4", True), ("^18.17.0", "20.1.0", False),
        ("^18.17.0", "18.16.0", False), ("^0.2.3", "0.3.0", False), ("^0.2.3", "0.2.9", True),
        ("~18.17.0", "18.20.0", False), ("~18.17", "18.17.9", True), ("18.x", "18.20.4", True),
        ("18", "19.0.0", False), ("*", "4.0.0", True), ("", "4.0.0", True),
        ("16.14 - 18", "18.20.4", True), ("16.14 - 18", "16.13.9", False),
        ("^16.14.0 || >=18.0.0", "17.0.0", False), ("^16.14.0 || >=18.0.0", "18.20.4", True),
        (">=14 <19", "18.20.4", True), (">= 14 < 18", "18.20.4", False), ("=18.20.4", "18.20.4", True),
        ("v18.20.4", "18.20.5", False),
    ]
    for i, (rng, version, want) in enumerate(cases):
        rc, out = check(lockfile(f"case{i}.json", [rng]), version)
        if rc != (0 if want else 1):
            fail(f"range {rng!r} on {version}: exit {rc} ({out.strip()}), "
                 f"expected {'satisfied' if want else 'not satisfied'}")

    for label, argv_lock, version, needle in [
        ("an unreadable range", lockfile("bad_range.json", [">=18 foo"]), DEBIAN_12_NODE, ">=18 foo"),
        ("a missing lockfile", os.path.join(work, "missing.json"), DEBIAN_12_NODE, "missing.json"),
        ("a bad version", shipped, "eighteen", "eighteen"),
    ]:
        rc, out = check(argv_lock, version)
        if rc != 2 or needle not in out:
            fail(f"{label}: exit {rc}, output {out!r} (expected exit 2 naming {needle!r})")
    print(f"PASS check_node_engines: the shipped lockfile on Node {DEBIAN_12_NODE}, "
          f"{len(cases)} ranges, bad input")


if __name__ == "__main__":
    main()
