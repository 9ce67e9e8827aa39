#!/usr/bin/env python3
"""Times forcegrasp and the PCL reference side by side on the same scenes.

    python3 scripts/bench_vs_pcl.py --forcegrasp PATH --pcl PATH [--runs R] [--json OUT]
                                    SCENE_DIR [SCENE_DIR ...]

Each SCENE_DIR (one per PCD encoding, named after it) holds scene folders with a
scene.json. For each folder, for each run, for each scene: forcegrasp and the PCL
reference each run as a whole process (`plan SCENE --json`), interleaved, the one that
goes first alternating from run to run, then /bin/true as the floor of spawning a process.
Wall time is measured around os.posix_spawn + os.wait4; stdout goes to a pipe and its
JSON gives the in-process timing_us. One untimed run of each program per scene first
warms the page cache; it runs under GNU time, whose %M is the program's own peak RSS. Exit codes 0 (grasp) and 3 (no_grasp)
are normal runs; any other, or output that is not JSON, is a failure: reported, and the
exit code is 1. Prints markdown tables per folder and overall. Stdlib only.

The peak RSS is not taken from wait4 here: a process spawned from Python starts at this
Python process's high-water mark (Linux keeps the spawning address space's across exec).
GNU time forks the program from its own small address space and reports the program's.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

FG, PCL, TRUE = "forcegrasp", "PCL", "/bin/true"
GNU_TIME = "/usr/bin/time"
NORMAL_EXIT = {0: "ok", 3: "no_grasp"}


def spawn(argv):
    """One process, stdout to a pipe, stderr to /dev/null: (exit code, wall ms, peak RSS KiB, stdout)."""
    r, w = os.pipe()  # both ends close-on-exec; the child's fd 1 is a dup2 of w
    actions = [(os.POSIX_SPAWN_DUP2, w, 1), (os.POSIX_SPAWN_OPEN, 2, os.devnull, os.O_WRONLY, 0)]
    t0 = time.perf_counter_ns()
    pid = os.posix_spawn(argv[0], argv, os.environ, file_actions=actions)
    os.close(w)  # so that the read below ends when the child exits
    chunks = []
    while chunk := os.read(r, 1 << 16):
        chunks.append(chunk)
    _, status, usage = os.wait4(pid, 0)
    wall_ms = (time.perf_counter_ns() - t0) / 1e6
    os.close(r)
    return os.waitstatus_to_exitcode(status), wall_ms, usage.ru_maxrss, b"".join(chunks)


def in_process_ms(stdout):
    """(timing_us.total, read + plan) of a plan's JSON in ms, or (None, None) when the output
    is not such JSON. The two programs' totals differ in scope: forcegrasp's starts at the
    ingest of the decoded clouds, PCL's includes loading the files. So read + plan is
    forcegrasp's process_read + process_plan (from opening the files to the report) and
    PCL's total: the in-process figures that compare alike."""
    try:
        t = json.loads(stdout)["timing_us"]
        total = t["total"] / 1000.0
        if "process_read" in t and "process_plan" in t:
            return total, (t["process_read"] + t["process_plan"]) / 1000.0
        return total, total
    except (ValueError, KeyError, TypeError):
        return None, None


class Bench:
    """The samples of one scene folder: samples[program][scene] = list of run records."""

    def __init__(self, programs, failures):
        self.programs = programs  # name -> path
        self.failures = failures  # shared across folders: "what failed" -> count
        self.samples = {name: {} for name in list(programs) + [TRUE]}
        self.rss_kib = {name: 0 for name in list(programs) + [TRUE]}  # the peak over the warm-up runs

    def fail(self, what):
        self.failures[what] = self.failures.get(what, 0) + 1

    def warm(self, scene):
        """One untimed run of each program: the page cache holds the clouds before timing.
        Run through subprocess so that a failing program's stderr can be shown."""
        for name, argv in [(n, [path, "plan", scene, "--json"]) for n, path in self.programs.items()] + [(TRUE, [TRUE])]:
            p = subprocess.run([GNU_TIME, "-f", "%M"] + argv, capture_output=True)
            lines = p.stderr.decode(errors="replace").strip().splitlines()
            if p.returncode not in NORMAL_EXIT:
                self.fail("%s exit %d on %s (warm-up; stderr: %s)" % (name, p.returncode, scene, " / ".join(lines[-3:])))
            elif lines and lines[-1].isdigit():
                self.rss_kib[name] = max(self.rss_kib[name], int(lines[-1]))

    def time_one(self, name, scene):
        if name == TRUE:
            argv = [TRUE]
        else:
            argv = [self.programs[name], "plan", scene, "--json"]
        code, wall_ms, _, stdout = spawn(argv)
        total_ms = read_plan_ms = None
        if name != TRUE:
            total_ms, read_plan_ms = in_process_ms(stdout)
            if code not in NORMAL_EXIT:
                self.fail("%s exit %d on %s" % (name, code, scene))
            elif total_ms is None:
                self.fail("%s printed no timing_us.total on %s" % (name, scene))
        record = {"wall_ms": wall_ms, "rss_kib": self.rss_kib[name], "total_ms": total_ms,
                  "read_plan_ms": read_plan_ms, "exit": code}
        self.samples[name].setdefault(scene, []).append(record)

    def run(self, scenes, runs):
        for scene in scenes:
            self.warm(scene)
        names = list(self.programs)
        for r in range(runs):
            # Alternating which program goes first evens out any advantage of going second
            # (caches warmed by the other, a CPU clock already up).
            order = names if r % 2 == 0 else names[::-1]
            for scene in scenes:
                for name in order + [TRUE]:
                    self.time_one(name, scene)


def merge(benches):
    """The samples of several folders as one (scene paths are distinct across folders)."""
    merged = {}
    for b in benches:
        for name, per_scene in b.samples.items():
            merged.setdefault(name, {}).update(per_scene)
    return merged


def summary(per_scene):
    """The figures of one program over all scenes x runs (times in ms)."""
    records = [rec for recs in per_scene.values() for rec in recs]
    walls = [rec["wall_ms"] for rec in records]

    def median_of(key):
        values = [rec[key] for rec in records if rec[key] is not None]
        return statistics.median(values) if values else None

    return {
        "min": min(walls), "median": statistics.median(walls), "max": max(walls),
        "scene_median": statistics.median(statistics.median(r["wall_ms"] for r in recs)
                                          for recs in per_scene.values()),
        "in_process": median_of("total_ms"),
        "read_plan": median_of("read_plan_ms"),
        "rss_mib": max(rec["rss_kib"] for rec in records) / 1024.0,
    }


def cell(value, fmt="%.1f"):
    return "-" if value is None else fmt % value


def ratio(a, b):
    return None if a is None or b is None or b == 0 else a / b


def table(title, samples):
    """A markdown table of forcegrasp, PCL, their ratio and the spawn floor."""
    s = {name: summary(per_scene) for name, per_scene in samples.items() if per_scene}
    lines = ["### " + title, "",
             "| program | min ms | median ms | max ms | median of scene medians ms | in-process total ms "
             "| in-process read+plan ms | peak RSS MiB |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for name in (FG, PCL, TRUE):
        f = s[name]
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
            name, cell(f["min"]), cell(f["median"]), cell(f["max"]), cell(f["scene_median"]),
            cell(f["in_process"]), cell(f["read_plan"]), cell(f["rss_mib"])))
    fg, pcl = s[FG], s[PCL]
    lines.append("| **PCL / forcegrasp** | | **%s** | | **%s** | **%s** | **%s** | |" % tuple(
        cell(ratio(pcl[k], fg[k]), "%.2f") for k in ("median", "scene_median", "in_process", "read_plan")))
    return "\n".join(lines)


def outcomes(samples):
    """Lines on the exit codes: how many scenes each program grasped, and where they differ."""
    def codes(name, scene):
        return sorted({rec["exit"] for rec in samples[name][scene]})

    def label(cs):
        return "/".join(NORMAL_EXIT.get(c, "exit %d" % c) for c in cs)

    def scene_name(scene):
        return os.path.basename(os.path.dirname(scene))

    lines = []
    for name in (FG, PCL):
        per = {sc: codes(name, sc) for sc in samples[name]}
        no_grasp = [scene_name(sc) for sc, c in per.items() if c == [3]]
        lines.append("%s: %d of %d scenes ok, %d no_grasp%s" % (
            name, sum(c == [0] for c in per.values()), len(per), len(no_grasp),
            " (%s)" % ", ".join(no_grasp) if no_grasp else ""))
    for scene in samples[FG]:
        fg, pcl = codes(FG, scene), codes(PCL, scene)
        if fg != pcl:
            lines.append("differ on %s: forcegrasp %s, PCL %s" % (scene_name(scene), label(fg), label(pcl)))
    return "; ".join(lines[:2]) + "".join("\n- " + line for line in lines[2:])


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def commit():
    p = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return p.stdout.strip() or "unknown"


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def scenes_in(folder):
    return sorted(os.path.join(folder, d, "scene.json") for d in os.listdir(folder)
                  if os.path.isfile(os.path.join(folder, d, "scene.json")))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--forcegrasp", required=True)
    ap.add_argument("--pcl", required=True)
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--json", help="write every run's record here")
    ap.add_argument("folders", nargs="+")
    a = ap.parse_args()
    programs = {FG: os.path.abspath(a.forcegrasp), PCL: os.path.abspath(a.pcl)}
    folders = {os.path.basename(os.path.normpath(f)): scenes_in(f) for f in a.folders}
    counts = sorted({len(s) for s in folders.values()})

    print("# forcegrasp vs PCL reference")
    print()
    print("- machine: %s, %d cores; load average before: %s" % (cpu_model(), os.cpu_count(), loadavg()))
    print("- commit: %s" % commit())
    print("- scenes: %s per encoding (%s), %d runs each, whole process = spawn to wait4"
          % ("/".join(map(str, counts)), ", ".join(folders), a.runs))
    print("- in-process: medians of the JSON's timing_us; forcegrasp's total leaves out the clouds it reads whole"
          " (its process_read; DATA binary clouds are read during the ingest), PCL's includes loading them:"
          " read+plan is the like-for-like figure (forcegrasp process_read + process_plan, PCL total)")
    print("- peak RSS: the program's own, as GNU time's %M reports it (the warm-up runs)")
    sys.stdout.flush()

    failures = {}
    benches = {}
    for enc, scenes in folders.items():
        print("timing %s: %d scenes x %d runs" % (enc, len(scenes), a.runs), file=sys.stderr)
        benches[enc] = Bench(programs, failures)
        benches[enc].run(scenes, a.runs)
        print()
        print(table(enc, benches[enc].samples))
        print()
        print(outcomes(benches[enc].samples))
        sys.stdout.flush()
    print()
    print(table("overall", merge(benches.values())))
    print()
    print("load average after: %s" % loadavg())
    if a.json:
        with open(a.json, "w") as f:
            json.dump({enc: b.samples for enc, b in benches.items()}, f, indent=1)
    if failures:
        print()
        print("## Failures")
        for what, n in failures.items():
            print("- %s (%d times)" % (what, n))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
