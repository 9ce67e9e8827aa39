#!/usr/bin/env python3
"""The whole plan's worst case against its typical case in time, measured fairly on a
shared machine (docs/worst-case-timing.md, "Where the 3x target stands").

fg_wcet times one case after another, so a burst of load from another tenant can land
on the worst case and miss the typical one (or the other way round): the time ratios of
one such run moved by a third. Here every case runs in rounds, each round running every
case once (fg_wcet --case NAME --runs N, a warm-up and N timed plans), so both ends of
each ratio see the same load. Per case: the median over the rounds of fg_wcet's median
`total` (ingest + plan()). The adversarial cases at the default options are set against
the reference typical case; each case that changes options against `typical_at_<case>`
(the typical input at those options). `hash_collide` is left out, as in the report.

usage: interleaved_ratio.py FG_WCET [--rounds R] [--runs N] [--json FILE]
Prints a Markdown table; exits 0 whatever the ratios (a measurement, not a test).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

from wcet_report import PATHOLOGICAL  # the cases the report leaves out too


def list_cases(exe):
    out = subprocess.run([exe, "--list"], check=True, capture_output=True, text=True).stdout
    cases = []
    for line in out.splitlines():
        if line.strip():
            cases.append((line.split()[0], "[typical]" in line))
    return cases


def run_case(exe, name, runs, tmp):
    path = os.path.join(tmp, name + ".json")
    subprocess.run([exe, "--case", name, "--runs", str(runs), "--quiet", "--json", path],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(path) as f:
        j = json.load(f)
    c = j["cases"][0]
    # A case this configuration cannot build reports an error instead (as in the report).
    return j, (c["stats"]["total"]["median"] if "error" not in c else None)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--json")
    a = ap.parse_args()

    cases = [(n, t) for n, t in list_cases(a.exe) if n not in PATHOLOGICAL]
    totals = {n: [] for n, _ in cases}
    ref = None
    load = [open("/proc/loadavg").read().split()[:3]]
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.rounds):
            for name, _ in cases:
                j, total = run_case(a.exe, name, a.runs, tmp)
                if ref is None:
                    ref = j["reference_typical"]
                if total is not None:
                    totals[name].append(total)
    load.append(open("/proc/loadavg").read().split()[:3])
    med = {n: statistics.median(v) for n, v in totals.items() if v}
    typical = {n for n, t in cases if t}

    rows = []
    for name, _ in cases:
        if name in typical or name not in med:
            continue
        base = "typical_at_" + name if "typical_at_" + name in totals else ref
        if base not in med:
            continue
        rows.append({"case": name, "against": base, "case_us": med[name], "typical_us": med[base],
                     "ratio": med[name] / med[base], "rounds_us": totals[name], "typical_rounds_us": totals[base]})

    print("Whole plan (`total`), median over %d interleaved rounds of fg_wcet's median of %d runs; "
          "load average %s before, %s after." % (a.rounds, a.runs, " ".join(load[0]), " ".join(load[1])))
    print()
    print("| case | against | typical ms | case ms | ratio |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %.2f | %.2f | %.2fx |" % (r["case"], r["against"], r["typical_us"] / 1000,
                                                    r["case_us"] / 1000, r["ratio"]))
    worst = max(rows, key=lambda r: r["ratio"])
    print()
    print("Largest ratio: %.2fx (%s against %s)." % (worst["ratio"], worst["case"], worst["against"]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rounds": a.rounds, "runs": a.runs, "load": load, "reference_typical": ref,
                       "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
