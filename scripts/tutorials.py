#!/usr/bin/env python3
"""Runs every shell block of the guide's tutorials (docs/src/tutorials/*.md), in order, and the
checks written under each block, so that the tutorials cannot rot.

Each page runs in a fresh scratch folder (or, with `<!-- tutorial: cwd=repo -->`, in the
repository's root), with `lopin` on the PATH (LOPIN_BIN, default: scripts/lopin-bin.sh) and
gmsh (LOPIN_GMSH, when set). A block runs under `bash -euo pipefail`; its checks are HTML
comments, invisible in the book:

    <!-- check: output REGEX -->        the block's stdout + stderr match REGEX
    <!-- check: file PATH -->           PATH exists and is not empty
    <!-- check: files GLOB N -->        GLOB matches exactly N files
    <!-- check: lines PATH N -->        PATH has exactly N lines
    <!-- check: contains PATH REGEX --> PATH's text matches REGEX
    <!-- check: json PATH EXPR -->      EXPR holds for d = the JSON of PATH
    <!-- check: serves URL -->          the block, started in the background, answers on URL
                                        (then it is stopped)

Usage: scripts/tutorials.py [PAGE.md ...]   (default: every tutorial, in the book's order)
"""
import glob
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK_TIMEOUT = 900


def blocks(text):
    """The page's sh blocks, each with the checks that follow it."""
    out = []
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        if lines[i].strip() == "```sh":
            j = i + 1
            while lines[j].strip() != "```":
                j += 1
            out.append({"line": i + 1, "code": "\n".join(lines[i + 1 : j]), "checks": []})
            i = j
        elif out:
            m = re.match(r"\s*<!-- check: (\w+) (.*) -->\s*$", lines[i])
            if m:
                out[-1]["checks"].append((m.group(1), m.group(2)))
        i += 1
    return out


def check(kind, arg, output, cwd):
    """None when the check holds, else why not."""
    path = lambda p: os.path.join(cwd, p)
    if kind == "output":
        return None if re.search(arg, output, re.M) else f"the output does not match /{arg}/"
    if kind == "file":
        ok = os.path.isfile(path(arg)) and os.path.getsize(path(arg)) > 0
        return None if ok else f"no file {arg} (or it is empty)"
    if kind == "files":
        pattern, n = arg.rsplit(" ", 1)
        found = len(glob.glob(path(pattern)))
        return None if found == int(n) else f"{pattern}: {found} files, not {n}"
    if kind == "lines":
        name, n = arg.rsplit(" ", 1)
        with open(path(name)) as f:
            count = sum(1 for _ in f)
        return None if count == int(n) else f"{name}: {count} lines, not {n}"
    if kind == "contains":
        name, pattern = arg.split(" ", 1)
        with open(path(name)) as f:
            text = f.read()
        return None if re.search(pattern, text, re.M) else f"{name} does not match /{pattern}/"
    if kind == "json":
        name, expr = arg.split(" ", 1)
        with open(path(name)) as f:
            d = json.load(f)
        here = os.getcwd()
        os.chdir(cwd)
        try:
            ok = eval(expr, {"json": json, "d": d})
        finally:
            os.chdir(here)
        return None if ok else f"{name}: {expr} does not hold"
    return f"unknown check `{kind}`"


def serve(code, url, cwd, env):
    """Starts the block, waits for url to answer, stops it."""
    p = subprocess.Popen(["bash", "-euo", "pipefail", "-c", code], cwd=cwd, env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         start_new_session=True)
    try:
        for _ in range(600):
            if p.poll() is not None:
                return p.stdout.read(), f"exited with {p.returncode} before serving {url}"
            try:
                urllib.request.urlopen(url, timeout=2).read()
                return "", None
            except Exception:
                time.sleep(0.1)
        return "", f"{url} does not answer"
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGTERM)
            p.wait()


def run_page(page, env):
    with open(page) as f:
        text = f.read()
    name = os.path.relpath(page, ROOT)
    bs = blocks(text)
    if not bs:
        print(f"tutorials: {name}: no sh block", file=sys.stderr)
        return False
    scratch = None
    if "<!-- tutorial: cwd=repo -->" in text:
        cwd = ROOT
    else:
        scratch = tempfile.mkdtemp(prefix="lopin-tutorial-")
        cwd = scratch
    ok = True
    for k, b in enumerate(bs, 1):
        start = time.time()
        serves = [a for (c, a) in b["checks"] if c == "serves"]
        if serves:
            output, failure = serve(b["code"], serves[0], cwd, env)
            failures = [failure] if failure else []
        else:
            try:
                r = subprocess.run(["bash", "-euo", "pipefail", "-c", b["code"]], cwd=cwd,
                                   env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                   text=True, timeout=BLOCK_TIMEOUT)
                output = r.stdout
                failures = [] if r.returncode == 0 else [f"exit status {r.returncode}"]
            except subprocess.TimeoutExpired as e:
                output = e.stdout or ""
                failures = [f"still running after {BLOCK_TIMEOUT} s"]
            if not failures:
                for c, a in b["checks"]:
                    try:
                        why = check(c, a, output, cwd)
                    except Exception as e:  # a file missing or not what it should be
                        why = f"check `{c} {a}`: {type(e).__name__}: {e}"
                    if why:
                        failures.append(why)
        took = time.time() - start
        if failures:
            ok = False
            print(f"tutorials: {name}:{b['line']}: block {k}/{len(bs)} FAILED ({took:.1f} s): "
                  + "; ".join(failures))
            print("---- the block\n" + b["code"] + "\n---- its output (end)\n" + output[-4000:])
            break
        print(f"tutorials: {name}:{b['line']}: block {k}/{len(bs)} ok, "
              f"{len(b['checks'])} checks ({took:.1f} s)")
    if scratch and ok:
        shutil.rmtree(scratch, ignore_errors=True)
    return ok


def main():
    pages = sys.argv[1:]
    if not pages:
        with open(os.path.join(ROOT, "docs/src/SUMMARY.md")) as f:
            pages = [os.path.join(ROOT, "docs/src", p)
                     for p in re.findall(r"\((tutorials/[^)]+\.md)\)", f.read())]
    lopin = os.environ.get("LOPIN_BIN") or subprocess.run(
        [os.path.join(ROOT, "scripts/lopin-bin.sh")], check=True, capture_output=True,
        text=True).stdout.strip()
    bin_dir = tempfile.mkdtemp(prefix="lopin-tutorial-bin-")
    os.symlink(os.path.abspath(lopin), os.path.join(bin_dir, "lopin"))
    if os.environ.get("LOPIN_GMSH"):
        os.symlink(os.environ["LOPIN_GMSH"], os.path.join(bin_dir, "gmsh"))
    env = dict(os.environ)
    env["PATH"] = bin_dir + os.pathsep + env.get("PATH", "")
    # mpirun as root on a CI machine, more ranks than cores
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    failed = [p for p in pages if not run_page(p, env)]
    shutil.rmtree(bin_dir, ignore_errors=True)
    if failed:
        sys.exit("tutorials: failed: " + ", ".join(os.path.relpath(p, ROOT) for p in failed))
    print(f"tutorials: {len(pages)} pages, every shell block ran and its checks held")


if __name__ == "__main__":
    main()
