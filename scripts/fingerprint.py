#!/usr/bin/env python3
"""Behaviour fingerprint of a `lopin` binary: ten configurations (runs, a sweep, a study) solved
with `--out`, and of each the converged interface fields s and ŝ (the body of `solution.bin` and
of every `value-*.state`, without the header that names what the file belongs to), the
iteration counts and the η histories, hashed.

    scripts/fingerprint.py record LOPIN > fingerprint.txt    # the fingerprint of one binary
    scripts/fingerprint.py compare fingerprint.txt LOPIN     # a binary against a stored one
    scripts/fingerprint.py compare OLD_LOPIN NEW_LOPIN       # two binaries, on this machine

A restructuring that leaves the solver's behaviour unchanged leaves every line identical.
Hashes of floating-point results are those of one machine: compare on the machine that
recorded them. Exit status 1 when a line differs.
"""

import csv
import hashlib
import json
import os
import subprocess
import sys
import tempfile

CONFIGS = [
    "run two-blocks",
    "run two-blocks --window whole",
    "run two-blocks --macro on",
    "run two-blocks --f 0.5",
    "run gap-impact",
    "run granular-small",
    "run two-blocks-ramp --rho-inf 0.5 --anderson 5",
    "run bar",
    "run granular-poly",
    "sweep two-blocks --param f=0:0.6:0.1",
    "study two-blocks --param f=0:0.4:0.2 --param gap=0:10e-6:5e-6",
]

HEADER, TRAILER = 16, 4


def body_hash(path):
    data = open(path, "rb").read()
    return hashlib.sha256(data[HEADER:-TRAILER]).hexdigest()[:16]


def history_hash(values):
    return hashlib.sha256(json.dumps(values).encode()).hexdigest()[:16]


def describe(folder):
    """One line per file of a run, sweep or study folder that carries results."""
    lines = []
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if name.endswith((".bin", ".state")):
            lines.append(f"{name} fields {body_hash(path)}")
        elif name.startswith("value-") and name.endswith(".json"):
            v = json.load(open(path))
            lines.append(f"{name} {v['iterations']} iterations, eta {history_hash(v['eta_history'])}")
        elif name == "run.json":
            r = json.load(open(path)).get("result")
            if r:
                lines.append(
                    f"run.json {r['iterations']} iterations, eta {r['eta']!r}, "
                    f"history {history_hash(r['eta_history'])}"
                )
        elif name == "study.csv":
            rows = list(csv.DictReader(open(path)))
            cols = [k for k in rows[0] if k not in ("wall_s", "checksum")]
            kept = [[r[k] for k in cols] for r in rows]
            lines.append(f"study.csv {len(rows)} rows {history_hash(kept)}")
    return lines


def record(lopin):
    out = []
    with tempfile.TemporaryDirectory() as work:
        for i, config in enumerate(CONFIGS):
            folder = os.path.join(work, str(i))
            done = subprocess.run(
                [lopin, *config.split(), "--out", folder],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                text=True,
            )
            if done.returncode != 0:
                out.append(f"{config} | failed: {done.stderr.strip()[-200:]}")
                continue
            out.extend(f"{config} | {line}" for line in describe(folder))
    return out


def stored_or_recorded(arg):
    if os.access(arg, os.X_OK) and not arg.endswith(".txt"):
        return record(arg)
    return [line.rstrip("\n") for line in open(arg) if line.strip()]


def main(argv):
    if len(argv) == 3 and argv[1] == "record":
        print("\n".join(record(argv[2])))
        return 0
    if len(argv) == 4 and argv[1] == "compare":
        old, new = stored_or_recorded(argv[2]), stored_or_recorded(argv[3])
        differ = [(a, b) for a, b in zip(old, new) if a != b]
        if len(old) != len(new):
            differ.append((f"{len(old)} lines", f"{len(new)} lines"))
        for a, b in differ:
            print(f"- {a}\n+ {b}")
        configs = len({line.split(" | ")[0] for line in new})
        print(f"{len(new)} lines over {configs} configurations: "
              f"{'IDENTICAL' if not differ else f'{len(differ)} DIFFERENT'}")
        return 1 if differ else 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
