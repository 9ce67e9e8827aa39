#!/usr/bin/env python3
"""Deepest stack path from the Planner's public entry points (docs/worst-case-timing.md).

Reads the GCC call-graph files (-fcallgraph-info=su, one .ci per object file: every
function's frame size and qualifier, and its call edges) of the given build folders,
and reports, per entry point, the call path with the largest sum of frame sizes.

Flags what a static bound cannot cover:
  * frames marked "dynamic" without "bounded" (alloca / VLA): unbounded;
  * recursion (a cycle in the call graph): a self-recursive function with a bound given
    by --recursion-bound NAME=DEPTH counts DEPTH frames, any other cycle is unbounded;
  * calls through pointers ("__indirect_call"): resolved to the functions named by
    --indirect CALLER=TARGET[,TARGET...], else flagged;
  * callees outside the files read (libm, libc builtins): their own stack is unknown,
    listed by name (a leaf of the reported path).

usage: stack_depth.py [--entry SUBSTR]... [--indirect CALLER=T1,T2]...
                      [--recursion-bound SUBSTR=DEPTH]... [--json FILE] DIR [DIR...]
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

NODE = re.compile(r'^node: \{ title: "(?P<title>[^"]*)" label: "(?P<label>(?:[^"\\]|\\.)*)"(?P<rest>[^}]*)\}')
EDGE = re.compile(r'^edge: \{ sourcename: "(?P<src>[^"]*)" targetname: "(?P<dst>[^"]*)"')
BYTES = re.compile(r'(\d+) bytes \(([a-z,]+)\)')

DEFAULT_ENTRIES = [
    "fg::Planner::configure(",
    "fg::Planner::reset(",
    "fg::Planner::add_points(",
    "fg::Planner::add_depth_image(",
    "fg::Planner::plan(",
    "fg::Planner::plan_object(",
    "fg::Planner::more_grasps(",
    "fg::Planner::analyze_view(",
]


def demangle(title):
    """A name for a node whose label GCC left unusable (e.g. "0(...)" for .part clones)."""
    sym = title.rsplit(":", 1)[-1]
    base, _, clone = sym.partition(".")
    name = base
    if shutil.which("c++filt"):
        try:
            name = subprocess.run(["c++filt", base], capture_output=True, text=True, check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            pass
    return name + ("  [." + clone + " clone]" if clone else "")


def read_graph(dirs):
    funcs = {}   # title -> dict(name, bytes, qual, file)
    names = {}   # title -> printable name (also for external nodes)
    edges = {}   # title -> set(titles)
    for d in dirs:
        for root, _, files in os.walk(d):
            for f in sorted(files):
                if not f.endswith(".ci"):
                    continue
                with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
                    for line in fh:
                        m = NODE.match(line)
                        if m:
                            title = m.group("title")
                            parts = m.group("label").split("\\n")
                            names.setdefault(title, parts[0])
                            if not re.match(r"^[A-Za-z_~]", parts[0].split("(")[0].split(" ")[-1] or "0"):
                                parts[0] = demangle(title)
                                names[title] = parts[0]
                            b = BYTES.search(m.group("label"))
                            if b:
                                funcs[title] = {"name": parts[0], "bytes": int(b.group(1)), "qual": b.group(2),
                                                "where": parts[1] if len(parts) > 1 else ""}
                                names[title] = parts[0]
                            continue
                        m = EDGE.match(line)
                        if m:
                            edges.setdefault(m.group("src"), set()).add(m.group("dst"))
    return funcs, names, edges


def short(name):
    """A readable function name: drop the return type, arguments and template noise."""
    n = name
    n = re.sub(r"\s*\[with .*\]$", "", n)
    depth, cut = 0, None
    for i, ch in enumerate(n):  # the argument list starts at the first '(' outside <>
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
        elif ch == "(" and depth == 0:
            cut = i
            break
    head = n[:cut] if cut is not None else n
    # drop the return type (the last space outside <> before the name)
    depth, last_space = 0, -1
    for i, ch in enumerate(head):
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
        elif ch == " " and depth == 0:
            last_space = i
    return head[last_space + 1:]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--entry", action="append", default=None)
    ap.add_argument("--indirect", action="append", default=[])
    ap.add_argument("--recursion-bound", action="append", default=[])
    ap.add_argument("--json")
    a = ap.parse_args()

    funcs, names, edges = read_graph(a.dirs)
    if not funcs:
        print("stack_depth: no .ci files with frame sizes under %s (build with -fstack-usage "
              "-fcallgraph-info=su)" % ", ".join(a.dirs), file=sys.stderr)
        return 2

    def find(substr):
        return [t for t in funcs if substr in funcs[t]["name"] or substr in t]

    # Indirect calls: CALLER=T1,T2 (substrings of names or titles).
    indirect = {}
    for spec in a.indirect:
        caller, _, targets = spec.partition("=")
        for c in find(caller):
            for t in targets.split(","):
                for tt in find(t):
                    indirect.setdefault(c, set()).add(tt)
    bounds = {}
    for spec in a.recursion_bound:
        name, _, depth = spec.partition("=")
        for t in find(name):
            bounds[t] = int(depth)

    flags = []

    def callees(t):
        out = set()
        for d in edges.get(t, ()):
            if d == "__indirect_call":
                if t in indirect:
                    out |= indirect[t]
                else:
                    out.add(d)
            else:
                out.add(d)
        return out

    # Longest path by DFS with memo; cycles detected with an on-stack set.
    memo = {}
    on_stack = set()

    def deepest(t):
        """(bytes, path, notes) of the deepest path starting at t (t's frame included)."""
        if t in memo:
            return memo[t]
        if t == "__indirect_call":
            return (0, [("<indirect call, unresolved>", 0, "")], {"unresolved indirect call"})
        if t not in funcs:
            return (0, [(names.get(t, t) + "  [external: own stack not known]", 0, "")], {"external:" + short(names.get(t, t))})
        f = funcs[t]
        notes = set()
        if f["qual"].startswith("dynamic") and "bounded" not in f["qual"]:
            notes.add("unbounded dynamic frame: " + short(f["name"]))
        on_stack.add(t)
        best = (0, [], set())
        for c in callees(t):
            if c == t:
                continue  # self recursion: handled below
            if c in on_stack:
                notes.add("recursion (cycle): %s -> %s" % (short(f["name"]), short(names.get(c, c))))
                continue
            r = deepest(c)
            notes |= r[2]
            if r[0] > best[0] or (r[0] == best[0] and not best[1]):
                best = r
        on_stack.discard(t)
        frames = 1
        label = short(f["name"])
        if t in callees(t):
            if t in bounds:
                frames = bounds[t]
                label += "  [recursive, depth <= %d]" % frames
                notes.add("bounded recursion: %s, depth <= %d" % (short(f["name"]), frames))
            else:
                notes.add("recursion without a bound: " + short(f["name"]))
                label += "  [recursive, depth unknown: counted once]"
        own = f["bytes"] * frames
        res = (own + best[0], [(label, own, f["qual"])] + best[1], notes)
        memo[t] = res
        return res

    entries = a.entry or DEFAULT_ENTRIES
    report = {"entries": []}
    for e in entries:
        ts = [t for t in funcs if funcs[t]["name"].split(" ", 1)[-1].startswith(e) or e in funcs[t]["name"]]
        for t in ts:
            total, path, notes = deepest(t)
            report["entries"].append({"entry": short(funcs[t]["name"]), "bytes": total,
                                      "path": [{"function": p[0], "bytes": p[1], "qualifier": p[2]} for p in path],
                                      "notes": sorted(notes)})
    report["entries"].sort(key=lambda r: -r["bytes"])
    for r in report["entries"]:
        print("%-36s %6d bytes" % (r["entry"], r["bytes"]))
        for p in r["path"]:
            print("    %6d  %s%s" % (p["bytes"], p["function"], "  (%s)" % p["qualifier"] if p["qualifier"] and p["qualifier"] != "static" else ""))
        for n in r["notes"]:
            print("    note: " + n)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(report, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
