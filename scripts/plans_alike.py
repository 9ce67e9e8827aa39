#!/usr/bin/env python3
"""Every target plans a scene exactly as the host does (scripts/cross.sh).

usage: plans_alike.py NAME HOST_PROGRAM 'TARGET COMMAND' SCENE.json [SCENE.json ...]

Runs `HOST_PROGRAM plan SCENE --json` and `TARGET COMMAND plan SCENE --json` (the target's
forcegrasp, e.g. under qemu) on each scene and compares the two reports but for their
timings: every key, string and number the same, bit for bit (the reports print floats
to their last bit). Prints one line per scene that differs, with the first difference,
then a summary; exits 1 when any scene differs or a program fails to report.
"""
import json
import shlex
import subprocess
import sys


def first_difference(a, b, path=""):
    """The path and values where a and b first differ, or None when they are equal."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return path, sorted(a.keys()), sorted(b.keys())
        for k in a:
            d = first_difference(a[k], b[k], path + "." + k)
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return path, len(a), len(b)
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, "%s[%d]" % (path, i))
            if d:
                return d
        return None
    # bool is an int in Python: compare the types too, so 1 and true differ.
    return None if type(a) is type(b) and a == b else (path, a, b)


def report(command, scene):
    out = subprocess.run(command + ["plan", scene, "--json"], capture_output=True, text=True)
    try:
        r = json.loads(out.stdout)
    except ValueError:
        return None, "exit %d, no JSON report: %s" % (out.returncode, out.stderr.strip()[:200])
    r.pop("timing_us", None)
    r["exit code"] = out.returncode  # compared with the rest
    return r, None


def main(argv):
    if len(argv) < 5:
        print(__doc__, file=sys.stderr)
        return 2
    name, host, target, scenes = argv[1], [argv[2]], shlex.split(argv[3]), argv[4:]
    different = 0
    for scene in scenes:
        h, err_h = report(host, scene)
        t, err_t = report(target, scene)
        if err_h or err_t:
            print("%s: %s: host %s, %s %s" % (name, scene, err_h or "ok", name, err_t or "ok"))
            different += 1
            continue
        d = first_difference(h, t)
        if d:
            print("%s: %s plans differently: at %s host %r, %s %r" % (name, scene, d[0] or "the top", d[1], name, d[2]))
            different += 1
    print("%s: %d of %d scenes planned exactly as on the host" % (name, len(scenes) - different, len(scenes)))
    return 1 if different else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
