#!/usr/bin/env python3
"""Markdown report of one scripts/wcet.sh configuration folder (build/h-wcet*/wcet).

Reads time.json (fg_wcet --runs N), ir/<case>.json (fg_wcet --once --ir under
callgrind), stack.json (stack_depth.py) and cg/<case>.inclusive.txt
(callgrind_annotate --inclusive=yes), and prints the tables of
docs/worst-case-timing.md for that configuration.

usage: wcet_report.py OUT_DIR
"""
import json
import os
import re
import sys

STAGES = ["ingest", "plane", "cluster", "frame", "xoy", "xoz", "select", "total"]
CALLS = ["reset", "add", "plan"]
PATHOLOGICAL = {"hash_collide"}


def load(path):
    with open(path) as f:
        return json.load(f)


def fmt_us(v):
    if v is None:
        return "-"
    if v >= 1000:
        return "{:,.0f}".format(v)
    if v >= 10:
        return "{:.0f}".format(v)
    return "{:.1f}".format(v)


def fmt_ir(v):
    if v is None:
        return "-"
    if v >= 1e9:
        return "{:.2f} G".format(v / 1e9)
    if v >= 1e6:
        return "{:.1f} M".format(v / 1e6)
    if v >= 1e3:
        return "{:.0f} k".format(v / 1e3)
    return "{:.0f}".format(v)


def ratio(w, t):
    if w is None or t is None:
        return "-"
    if t <= 0:
        return "-" if w <= 0 else "inf"
    r = w / t
    return ("**{:.0f}x**" if r > 3 else "{:.1f}x").format(r) if r >= 10 else ("**{:.1f}x**" if r > 3 else "{:.1f}x").format(r)


def status(c):
    s = c.get("status", "?")
    if s == "no_grasp":
        s += "/" + c.get("reason", "")
    if c.get("add_status", "ok") != "ok":
        s = "add " + c["add_status"] + ", " + s
    return s


def top_functions(path, n=6):
    """The n largest inclusive costs of fg:: functions (one entry per function)."""
    best = {}
    if not os.path.exists(path):
        return []
    line_re = re.compile(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(\S.*)$")
    with open(path, errors="replace") as f:
        for line in f:
            m = line_re.match(line)
            if not m:
                continue
            ir = int(m.group(1).replace(",", ""))
            fn = re.sub(r"\s*\[[^\]]*\]\s*$", "", m.group(2))  # object file
            src = ""
            if ":" in fn and not fn.startswith("fg::"):
                src, fn = fn.split(":", 1)
            if not fn.startswith("fg::") or "wcet" in fn:
                continue
            anon = "(anonymous namespace)" in fn
            fn = re.sub(r"\(.*", "", fn.replace("(anonymous namespace)", "{anon}"))
            if anon:  # e.g. cluster.cpp's and hull.cpp's flood()
                if not src.endswith(".cpp"):
                    continue  # a header's inlined lines attributed to the caller
                fn = os.path.basename(src) + ":" + fn
            if fn in ("fg::Planner::plan", "fg::Planner::add_points", "fg::Planner::add_depth_image"):
                continue
            best[fn] = max(best.get(fn, 0), ir)
    return sorted(((v, k) for k, v in best.items()), reverse=True)[:n]


def main():
    d = sys.argv[1]
    t = load(os.path.join(d, "time.json"))
    ir = {}
    ir_dir = os.path.join(d, "ir")
    if os.path.isdir(ir_dir):
        for f in sorted(os.listdir(ir_dir)):
            if f.endswith(".json"):
                j = load(os.path.join(ir_dir, f))
                for c in j["cases"]:
                    ir[c["name"]] = c
    cases = [c for c in t["cases"] if "error" not in c]
    by_name = {c["name"]: c for c in cases}
    ref = t["reference_typical"]
    lim = t["limits"]
    size = t["sizeof_planner"]
    budget = 4 * 1024 * 1024 if lim == "host" else 512 * 1024
    load_before = open(os.path.join(d, "loadavg_before.txt")).read().strip() if os.path.exists(os.path.join(d, "loadavg_before.txt")) else "?"
    load_after = open(os.path.join(d, "loadavg_after.txt")).read().strip() if os.path.exists(os.path.join(d, "loadavg_after.txt")) else "?"

    p = print
    p("### Configuration `%s`" % lim)
    p()
    caps = t["capacities"]
    p("Capacities: " + ", ".join("%s %s" % (k, "{:,}".format(v)) for k, v in caps.items()) + ".")
    p()
    p("`sizeof(fg::Planner)` = **{:,} bytes** ({:.2f} MiB; target under {}: {}).".format(
        size, size / 1048576.0, "4 MiB" if lim == "host" else "512 KiB", "met" if size < budget else "**not met**"))
    p()
    p("Adversarial inputs offer {:,} points per sensor (two sensors). Reference typical case: `{}`. "
      "Time: {} runs per case after one warm-up run, load average {} before and {} after.".format(
          t["points_per_sensor"], ref, t["runs"], load_before, load_after))
    p()

    # Per-stage bound table: adversarial inputs at the default options against the
    # reference typical input; the cases that change options against the typical input
    # planned with the same options (typical_at_<case>).
    adversarial = [c for c in cases if not c["typical"] and c["name"] not in PATHOLOGICAL]
    at_defaults = [c for c in adversarial if not c.get("overrides")]
    with_options = [c for c in adversarial if c.get("overrides")]
    p("#### Per-stage bound at the default options (typical `%s` against the largest adversarial value)" % ref)
    p()
    p("Cases: " + ", ".join("`%s`" % c["name"] for c in at_defaults) + ".")
    p()
    p("| stage | typical us | worst us | case | ratio | largest single run us | typical Ir | worst Ir | case | ratio |")
    p("|---|---|---|---|---|---|---|---|---|---|")
    for s in STAGES + CALLS:
        tr = by_name.get(ref)
        t_typ = tr["stats"][s]["median"] if tr else None
        worst_t, worst_tc = None, "-"
        for c in at_defaults:
            v = c["stats"][s]["median"]
            if worst_t is None or v > worst_t:
                worst_t, worst_tc = v, c["name"]
        run_max = max([c["stats"][s]["max"] for c in at_defaults] + [0.0])
        i_typ = ir[ref]["stats"][s]["median"] if ref in ir else None
        worst_i, worst_ic = None, "-"
        for c in at_defaults:
            if c["name"] in ir:
                v = ir[c["name"]]["stats"][s]["median"]
                if worst_i is None or v > worst_i:
                    worst_i, worst_ic = v, c["name"]
        label = s if s in STAGES else "`%s()` call" % s
        p("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            label, fmt_us(t_typ), fmt_us(worst_t), worst_tc, ratio(worst_t, t_typ), fmt_us(run_max),
            fmt_ir(i_typ), fmt_ir(worst_i), worst_ic, ratio(worst_i, i_typ)))
    p()
    if with_options:
        p("#### Cases that change options, against the typical input at the same options")
        p()
        p("`typical_at_<case>` plans the reference typical input with the options the case changes. "
          "Per case: the whole plan (`total`) and the stage with the largest instruction ratio.")
        p()
        p("| case | changed options | typical total us | case total us | ratio | typical total Ir | case total Ir | ratio | largest stage ratio (Ir) |")
        p("|---|---|---|---|---|---|---|---|---|")
        for c in with_options:
            tn = "typical_at_" + c["name"]
            tc = by_name.get(tn)
            t_typ = tc["stats"]["total"]["median"] if tc else None
            t_case = c["stats"]["total"]["median"]
            i_typ = ir[tn]["stats"]["total"]["median"] if tn in ir else None
            i_case = ir[c["name"]]["stats"]["total"]["median"] if c["name"] in ir else None
            worst_stage, worst_r = "-", None
            if tn in ir and c["name"] in ir:
                for s in STAGES[:-1]:
                    a, b = ir[c["name"]]["stats"][s]["median"], ir[tn]["stats"][s]["median"]
                    if b > 0 and (worst_r is None or a / b > worst_r):
                        worst_stage, worst_r = s, a / b
            p("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                c["name"], ", ".join("`%s`" % o for o in c["overrides"]), fmt_us(t_typ), fmt_us(t_case),
                ratio(t_case, t_typ), fmt_ir(i_typ), fmt_ir(i_case), ratio(i_case, i_typ),
                "-" if worst_r is None else "%s %s" % (worst_stage, ratio(worst_r, 1.0))))
        p()
    p("Times are medians of the runs (typical: the reference case's; worst: the largest median over the "
      "adversarial cases of the table, `hash_collide` apart); the largest single run includes the scheduler's noise on "
      "a shared machine. Instruction counts are exact and repeatable. Ratios above 3x in bold.")
    p()
    p("The stages are the planner's own timers (`PlanResult::stage_us`); `ingest` is what the planner "
      "records inside `add_*` (not the sight-map reset before its timer starts), `total` = ingest + "
      "the whole of `plan()`. The `reset()`, `add_*()` and `plan()` rows time the whole public calls "
      "(`add` = both sensors).")
    p()

    # Instructions per case.
    if ir:
        p("#### Instructions per case (callgrind, one run; Ir)")
        p()
        p("| case | status | " + " | ".join(STAGES + CALLS) + " |")
        p("|---|---|" + "---|" * len(STAGES + CALLS))
        for c in cases:
            if c["name"] not in ir:
                continue
            j = ir[c["name"]]
            p("| %s | %s | %s |" % (c["name"], status(j), " | ".join(fmt_ir(j["stats"][s]["median"]) for s in STAGES + CALLS)))
        p()

    # Time per case.
    p("#### Time per case (us, median / max of %d runs)" % t["runs"])
    p()
    p("| case | status | " + " | ".join(STAGES + CALLS) + " |")
    p("|---|---|" + "---|" * len(STAGES + CALLS))
    for c in cases:
        p("| %s | %s | %s |" % (c["name"], status(c), " | ".join(
            "%s / %s" % (fmt_us(c["stats"][s]["median"]), fmt_us(c["stats"][s]["max"])) for s in STAGES + CALLS)))
    p()

    # What each case did.
    p("#### What each case put in and what the planner did")
    p()
    p("| case | input | changed options | voxels / object / views / candidates | capacities reached, behaviour | hash max displacement | stack high-water (B) |")
    p("|---|---|---|---|---|---|---|")
    for c in cases:
        p("| %s | %s | %s | %s / %s / %s / %s | %s | %s | %s |" % (
            c["name"], c.get("note", ""), ", ".join("`%s`" % o for o in c.get("overrides", [])) or "-",
            "{:,}".format(c["voxels"]), "{:,}".format(c["object_points"]), c["viewpoints"], c["candidates"],
            "; ".join(c.get("saturated", [])) or "-", c.get("hash_max_displacement", "-"),
            "{:,}".format(c["stack_high_water_bytes"]) if "stack_high_water_bytes" in c else "-"))
    p()
    for c in cases:
        if c.get("problems"):
            p("**Undefined outcome in `%s`:** %s" % (c["name"], "; ".join(c["problems"])))
            p()

    # Pathological hashing.
    for name in PATHOLOGICAL:
        if name in by_name:
            c = by_name[name]
            p("#### `%s` (%s)" % (name, c.get("note", "")))
            p()
            line = "Time (us, median / max): " + ", ".join(
                "%s %s / %s" % (s, fmt_us(c["stats"][s]["median"]), fmt_us(c["stats"][s]["max"])) for s in ["ingest", "cluster", "total", "reset"])
            p(line + ".")
            if name in ir:
                j = ir[name]
                p("Instructions: " + ", ".join("%s %s" % (s, fmt_ir(j["stats"][s]["median"])) for s in ["ingest", "cluster", "total", "reset"]) + ".")
            p()

    # Stack.
    sp = os.path.join(d, "stack.json")
    if os.path.exists(sp):
        st = load(sp)
        p("#### Stack (static, from `-fstack-usage -fcallgraph-info=su`)")
        p()
        p("| entry point | deepest path (frame bytes) | total bytes |")
        p("|---|---|---|")
        for e in st["entries"]:
            path = " -> ".join("%s (%d)" % (x["function"].split("  [")[0], x["bytes"]) for x in e["path"])
            p("| `%s` | %s | %d |" % (e["entry"], path, e["bytes"]))
        p()
        notes = set()
        for e in st["entries"]:
            notes |= set(e["notes"])
        ext = sorted(n.split(":", 1)[1] for n in notes if n.startswith("external:"))
        other = sorted(n for n in notes if not n.startswith("external:"))
        if other:
            p("Flags: " + "; ".join(other) + ".")
            p()
        if ext:
            p("External callees (own frames not in the files; libm/libc leaves): " + ", ".join("`%s`" % e for e in ext) + ".")
            p()

    # Hottest functions.
    cg = os.path.join(d, "cg")
    if os.path.isdir(cg):
        p("#### Where the instructions go (inclusive Ir, callgrind_annotate)")
        p()
        for c in cases:
            tops = top_functions(os.path.join(cg, c["name"] + ".inclusive.txt"))
            if tops:
                p("- `%s`: " % c["name"] + ", ".join("%s %s" % (fn, fmt_ir(v)) for v, fn in tops))
        p()
    return 0


if __name__ == "__main__":
    sys.exit(main())
