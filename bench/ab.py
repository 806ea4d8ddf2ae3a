#!/usr/bin/env python3
"""Side-by-side speed of two or more ophis builds (or settings) on one scene, one thread each.

Renders the scene with each command in turn, `--pairs` rounds, alternating, so that changes in
the machine's load fall on all of them alike; reads each render's CPU seconds from ophis's
summary line and prints the median per command and, for every command after the first, the
mean ratio first ÷ it (> 1: it is faster) with its standard error over the rounds.

A command is an ophis binary, optionally preceded by environment settings, e.g.

    python3 bench/ab.py --scene cornell-mesh --spp 16 \\
        /tmp/ophis-before target/release/ophis "OPHIS_PACKETS=0 target/release/ophis"

usage: python3 bench/ab.py [--scene cornell-box] [--spp 32] [--pairs 6] [--threads 1]
                           [-D name=value ...] COMMAND COMMAND [COMMAND ...]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def render(command, scene, spp, threads, defines):
    parts = command.split()
    env = dict(os.environ)
    while parts and "=" in parts[0]:
        key, value = parts.pop(0).split("=", 1)
        env[key] = value
    if not parts:
        sys.exit("no binary in command %r" % command)
    out = os.path.join(ROOT, "target", "bench", "ab.exr")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    cmd = parts + ["render", scene, "-Dspp=%d" % spp, "-o", out, "--quiet",
                   "--threads", str(threads)] + ["-D" + d for d in defines]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit("%s failed:\n%s" % (command, p.stderr))
    m = re.search(r" s, ([0-9.]+) CPU s,", p.stderr)
    if m is None:
        sys.exit("%s printed no CPU time:\n%s" % (command, p.stderr))
    return float(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="cornell-box",
                    help="a scene of scenes/ by name, or a path to an XML file")
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--pairs", type=int, default=6)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-D", dest="defines", action="append", default=[])
    ap.add_argument("commands", nargs="+")
    a = ap.parse_args()
    if len(a.commands) < 2:
        sys.exit("give two commands or more")
    scene = a.scene
    if not os.path.exists(scene):
        scene = os.path.join(ROOT, "scenes", a.scene + ".xml")
    cpu = [[] for _ in a.commands]
    for _ in range(a.pairs):
        for j, c in enumerate(a.commands):
            cpu[j].append(render(c, scene, a.spp, a.threads, a.defines))
    print("%s, %d spp, %d thread(s), %d rounds: render CPU s, median (min-max)"
          % (os.path.basename(scene), a.spp, a.threads, a.pairs))
    for j, c in enumerate(a.commands):
        print("  %-50s %.3f (%.3f-%.3f)" % (c, statistics.median(cpu[j]), min(cpu[j]),
                                             max(cpu[j])))
    for j in range(1, len(a.commands)):
        r = [x / y for x, y in zip(cpu[0], cpu[j])]
        se = statistics.stdev(r) / len(r) ** 0.5 if len(r) > 1 else float("nan")
        print("  first / %-42s %.3fx (standard error %.3f)" % (a.commands[j],
                                                               statistics.mean(r), se))


if __name__ == "__main__":
    main()
