#!/usr/bin/env python3
"""The twelve-seed simulation the README quotes, and a per-trial comparison of two runs.

  sim_seeds.py run FORCEGRASP OUT_DIR [--seeds twelve|fresh|further|blind|wide|5000,...] [--jobs 2]
                 [--trials 380] [--objects all] [--distribution classic|cell]
      runs `FORCEGRASP sim --distribution D --objects KINDS --trials N --seed S --quiet
      --json OUT_DIR/S.json` for every seed (two at a time by default) and prints the
      summary of OUT_DIR. The named sets are seeds of the classic distribution (the
      default here; the program's own default is cell).
      `--seeds blind` is the hold-out nobody looks into: totals only (SEED_SETS).
      `--seeds wide` runs the four kinds too wide to grasp, 2,000 trials per seed.
  sim_seeds.py summary DIR
      per seed successes; targets that fit; targets too wide and the trials that failed them.
  sim_seeds.py compare BASE_DIR NEW_DIR
      every trial whose verdict changed, and the totals of both.
  sim_seeds.py kinds DIR [DIR ...]
      per kind over all the runs given: right of trials (not for a blind run).

Trial i of a seed S runs seed S + i on kind i modulo the number of kinds; `forcegrasp sim
--distribution classic --objects KIND --trials 1 --seed S+i` reproduces it alone (with
--pictures / --export to look at it).
"""
import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

# Eight seeds tuned against and four held out (README, "Simulation").
SEEDS = [5000, 1000, 9000, 12000, 31000, 47000, 61000, 83000, 2000, 3000, 7000, 11000]
# Named sets for --seeds. "twelve": the above. "fresh": held out at first; its failures
# were looked at since. "further": held out at first too, to check a change chosen on the
# others. "blind": a hold-out whose trials nobody looks at, so its totals
# stay an unbiased estimate of what unseen scenes get: a run of it records that in
# OUT_DIR, and summary and compare then print totals only.
SEED_SETS = {
    "twelve": SEEDS,
    "fresh": [100000 * k for k in range(1, 9)],
    "further": [100000 * k for k in range(17, 25)],
    "blind": [100000 * k for k in range(9, 17)],
    # The four kinds too wide to grasp only (1,000 trials per kind): issue 3 asks for
    # `no_grasp` on every one, which the mixed sets sample 640 at a time.
    "wide": [3000000, 4000000],
}
# Sets that run other objects or another count than `--objects all --trials 380`.
SET_OBJECTS = {"wide": "wide_box,big_sphere,ycb_master_chef_can,ycb_scissors"}
SET_TRIALS = {"wide": 2000}
BLIND_MARK = "BLIND"


def load(dir_):
    runs = {}
    for name in sorted(os.listdir(dir_)):
        if name.endswith(".json"):
            with open(os.path.join(dir_, name)) as f:
                runs[int(name[:-5])] = json.load(f)["trials"]
    if not runs:
        sys.exit(f"sim_seeds.py: no <seed>.json in {dir_}")
    return runs


def is_blind(dir_):
    return os.path.exists(os.path.join(dir_, BLIND_MARK))


def summary(dir_):
    runs = load(dir_)
    total = ok = fit_n = fit_ok = wide_n = wide_ok = 0
    per_seed = []
    wide_fail = []
    for seed, trials in runs.items():
        s_ok = sum(t["success"] for t in trials)
        per_seed.append(f"{seed}:{s_ok}")
        total += len(trials)
        ok += s_ok
        for t in trials:
            if t["fits"]:
                fit_n += 1
                fit_ok += t["success"]
            else:
                wide_n += 1
                wide_ok += t["success"]
                if not t["success"]:
                    wide_fail.append(f'{t["kind"]} {t["seed"]} {t["verdict"]}')
    print(f"{ok}/{total} ({' '.join(per_seed)})")
    if fit_n:
        print(f"targets that fit: {fit_ok}/{fit_n} = {100.0 * fit_ok / fit_n:.1f}%")
    print(f"targets too wide: {wide_ok}/{wide_n}")
    if is_blind(dir_):
        return
    for line in wide_fail:
        print("  " + line)


def compare(base_dir, new_dir):
    base, new = load(base_dir), load(new_dir)
    blind = is_blind(base_dir) or is_blind(new_dir)
    gained = lost = 0
    for seed in sorted(set(base) & set(new)):
        for a, b in zip(base[seed], new[seed]):
            if a["verdict"] != b["verdict"] or a["success"] != b["success"]:
                mark = "+" if b["success"] and not a["success"] else "-" if a["success"] and not b["success"] else " "
                gained += mark == "+"
                lost += mark == "-"
                if not blind:
                    print(f'{mark} {a["kind"]:22} {a["seed"]:6}  {a["verdict"]}  ->  {b["verdict"]}')
    print(f"gained {gained}, lost {lost}")
    for d in (base_dir, new_dir):
        print(f"{d}: ", end="")
        summary(d)


def kinds(dirs):
    """Per kind over the runs in every dir: trials, right, rate (the README's table)."""
    rows = {}
    for d in dirs:
        if is_blind(d):
            sys.exit(f"sim_seeds.py: {d} is a blind run: its totals only")
        for trials in load(d).values():
            for t in trials:
                n, ok = rows.get(t["kind"], (0, 0))
                rows[t["kind"]] = (n + 1, ok + t["success"])
    for kind, (n, ok) in sorted(rows.items()):
        print(f"{kind:22} {ok:5}/{n:<5} {100.0 * ok / n:5.1f}%")


def run(binary, out_dir, seeds, jobs, trials, blind, objects, distribution):
    os.makedirs(out_dir, exist_ok=True)
    if blind:
        with open(os.path.join(out_dir, BLIND_MARK), "w") as f:
            f.write("a blind hold-out run: report its totals only\n")

    def one(seed):
        cmd = [binary, "sim", "--distribution", distribution, "--objects", objects, "--trials", str(trials),
               "--seed", str(seed), "--quiet", "--json", os.path.join(out_dir, f"{seed}.json")]
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            sys.exit(f"sim_seeds.py: seed {seed} exited {r.returncode}: {r.stderr.strip()}")

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        list(pool.map(one, seeds))
    summary(out_dir)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("forcegrasp")
    r.add_argument("out_dir")
    r.add_argument("--seeds", default="twelve",
                   help="a named set (" + ", ".join(SEED_SETS) + ") or comma-separated seeds")
    r.add_argument("--jobs", type=int, default=2)
    r.add_argument("--trials", type=int, default=None, help="trials per seed (380; 2000 for wide)")
    r.add_argument("--objects", default=None, help="kinds for `forcegrasp sim --objects` (all; the four too wide for wide)")
    r.add_argument("--distribution", default="classic", choices=["classic", "cell"],
                   help="scenes of `forcegrasp sim --distribution` (classic: the sets' seeds are of it)")
    s = sub.add_parser("summary")
    s.add_argument("dir")
    c = sub.add_parser("compare")
    c.add_argument("base_dir")
    c.add_argument("new_dir")
    k = sub.add_parser("kinds")
    k.add_argument("dirs", nargs="+")
    a = p.parse_args()
    if a.cmd == "run":
        seeds = SEED_SETS.get(a.seeds) or [int(x) for x in a.seeds.split(",")]
        trials = a.trials if a.trials is not None else SET_TRIALS.get(a.seeds, 380)
        objects = a.objects if a.objects is not None else SET_OBJECTS.get(a.seeds, "all")
        run(a.forcegrasp, a.out_dir, seeds, a.jobs, trials, a.seeds == "blind", objects, a.distribution)
    elif a.cmd == "summary":
        summary(a.dir)
    elif a.cmd == "kinds":
        kinds(a.dirs)
    else:
        compare(a.base_dir, a.new_dir)


if __name__ == "__main__":
    main()
