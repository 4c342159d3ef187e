#!/usr/bin/python3
"""What compiling a set of source files costs at two revisions: CPU seconds (user + system, from
the kernel's accounting, so a shared machine's load barely moves them) per translation unit,
their sum and the largest one (the longest single step, which bounds a parallel build's wall
time). Each revision is checked out into a temporary git worktree and every .cpp under the given
folders that differs between the two revisions is compiled there, one at a time, with the flags
the build tree's compile_commands.json gives a file of the same library (no ccache).

    /usr/bin/python3 scripts/compile_cost.py --build build REV_A REV_B DIR [DIR ...]

Debian's /usr/bin/python3, standard library only. Exit 2 on bad usage; 1 when a file fails to
compile (its error printed). docs/ci.md ("Issue 52's splits") has the figures it measured.
"""

import argparse
import json
import os
import resource
import shlex
import subprocess
import sys
import tempfile


def fail(message, code=2):
    print(f"compile_cost: {message}", file=sys.stderr)
    sys.exit(code)


def git(*args, cwd):
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True,
                          text=True).stdout


def changed_sources(root, rev_a, rev_b, dirs):
    """The .cpp files under `dirs` that differ between the revisions, as they are at each."""
    out = git("diff", "--name-status", "--no-renames", rev_a, rev_b, "--", *dirs, cwd=root)
    at_a, at_b = [], []
    for line in out.splitlines():
        status, path = line.split("\t", 1)
        if not path.endswith(".cpp"):
            continue
        if status != "A":
            at_a.append(path)
        if status != "D":
            at_b.append(path)
    return at_a, at_b


def flag_templates(build, root):
    """Per source file, its compile command; per source folder, one of its files' (the flags of
    the library a file that the build tree lacks most likely belonged to)."""
    db = os.path.join(build, "compile_commands.json")
    try:
        with open(db, encoding="utf-8") as f:
            entries = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{db}: {e} (configure the build tree first)")
    templates = {}
    for e in entries:
        rel = os.path.relpath(e["file"], root)
        if rel.startswith("..") or rel.startswith("tests") or rel.startswith("fuzz"):
            continue
        args = shlex.split(e["command"])
        if args and os.path.basename(args[0]) == "ccache":
            args = args[1:]
        templates[rel] = (args, e["directory"])
        templates.setdefault(os.path.dirname(rel), (args, e["directory"]))
    return templates


def compile_seconds(args, directory):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(args, cwd=directory, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        print(proc.stderr[-4000:], file=sys.stderr)
        fail(f"{args[-1]} did not compile", 1)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def measure(root, build, rev, files, templates):
    results = []
    with tempfile.TemporaryDirectory(prefix="compile_cost.") as tmp:
        tree = os.path.join(tmp, "tree")
        git("worktree", "add", "--detach", "--quiet", tree, rev, cwd=root)
        try:
            for path in files:
                folder = path if path in templates else os.path.dirname(path)
                while folder not in templates and folder:
                    folder = os.path.dirname(folder)
                if folder not in templates:
                    fail(f"no compile command in {build} for a file under {os.path.dirname(path)}")
                template, directory = templates[folder]
                # The checkout's include root becomes the revision's; the build tree's generated
                # headers (the SDK version) stay.
                args = [f"-I{tree}" if a == f"-I{root}" else a for a in template]
                o = args.index("-o")
                c = args.index("-c")
                args[o + 1] = os.devnull
                args[c + 1] = os.path.join(tree, path)
                results.append((path, compile_seconds(args, directory)))
        finally:
            git("worktree", "remove", "--force", tree, cwd=root)
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build", help="a configured build tree (Release)")
    parser.add_argument("rev_a")
    parser.add_argument("rev_b")
    parser.add_argument("dirs", nargs="+", help="source folders, relative to the checkout")
    a = parser.parse_args()
    root = git("rev-parse", "--show-toplevel", cwd=os.getcwd()).strip()
    build = os.path.abspath(a.build)
    for rev in (a.rev_a, a.rev_b):
        if subprocess.run(["git", "rev-parse", "--verify", "--quiet", rev + "^{commit}"], cwd=root,
                          capture_output=True).returncode != 0:
            fail(f"{rev}: not a commit")
    templates = flag_templates(build, root)
    at_a, at_b = changed_sources(root, a.rev_a, a.rev_b, a.dirs)
    for rev, files in ((a.rev_a, at_a), (a.rev_b, at_b)):
        results = measure(root, build, rev, files, templates)
        total = sum(s for _, s in results)
        largest = max(results, key=lambda r: r[1]) if results else ("-", 0.0)
        print(f"{rev}: {len(results)} files, {total:.1f} CPU s in all, largest "
              f"{largest[0]} {largest[1]:.1f} s")
        for path, s in sorted(results, key=lambda r: -r[1]):
            print(f"  {s:7.2f}  {path}")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
