#!/usr/bin/env python3
"""Replay time of each apitrace capture on tiler beside llvmpipe's, in one session (issue 17).

For every capture (default: the glmark2 traces of `../shared/traces/glmark2`, or of
`$TILER_ASSETS/traces/glmark2`), runs `tiler analyze CAPTURE` and Mesa's
`eglretrace --headless --benchmark CAPTURE` alternately, round after round, so that both see
the same machine, and prints a markdown table of medians:

- tiler's whole process (reading, translating, compiling and rendering every frame, the
  report printed), as a user waits for it;
- llvmpipe's replay time as `eglretrace --benchmark` reports it ("Rendered N frames in S
  secs"), and its whole process (EGL and Mesa start-up included);
- the ratios of tiler's time to each (below 1: tiler is faster).

    cargo build --release -p tiler-cli
    python3 bench/replay-llvmpipe.py --rounds 9                 # every capture
    python3 bench/replay-llvmpipe.py --rounds 5 desktop shadow  # some of them

Needs Debian's `apitrace` (eglretrace) and Mesa (`libegl-mesa0 libgl1-mesa-dri`); nothing else
but the standard library. The machine is noisy: quote medians of several rounds, and compare
only figures taken in the same session.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def default_traces():
    assets = os.environ.get("TILER_ASSETS")
    base = assets if assets else os.path.join(ROOT, "..", "shared")
    return os.path.normpath(os.path.join(base, "traces", "glmark2"))


def timed(cmd, env=None):
    start = time.perf_counter()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return elapsed, p.stdout


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("names", nargs="*", help="captures by name (file stem); default every .trace")
    parser.add_argument("--tiler", default=os.path.join(ROOT, "target", "release", "tiler"))
    parser.add_argument("--traces", default=default_traces(), help="folder of .trace files")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()

    if not os.path.isfile(args.tiler):
        sys.exit(f"no tiler binary at {args.tiler}: run `cargo build --release -p tiler-cli` first")
    if shutil.which("eglretrace") is None:
        sys.exit("eglretrace not found: install Debian's apitrace, libegl-mesa0 and libgl1-mesa-dri")
    if not os.path.isdir(args.traces):
        sys.exit(f"no captures folder at {args.traces}")
    names = args.names or sorted(f[: -len(".trace")] for f in os.listdir(args.traces) if f.endswith(".trace"))
    missing = [n for n in names if not os.path.isfile(os.path.join(args.traces, n + ".trace"))]
    if missing:
        sys.exit(f"no such capture in {args.traces}: {', '.join(missing)}")

    env = dict(os.environ, WAFFLE_PLATFORM="surfaceless_egl")
    tiler = {n: [] for n in names}
    replay = {n: [] for n in names}
    process = {n: [] for n in names}
    for round_ in range(args.rounds):
        for n in names:
            trace = os.path.join(args.traces, n + ".trace")
            tiler[n].append(timed([args.tiler, "analyze", trace])[0])
            elapsed, out = timed(["eglretrace", "--headless", "--benchmark", trace], env)
            m = re.search(r"Rendered \d+ frames in ([0-9.]+) secs", out)
            if not m:
                raise RuntimeError(f"eglretrace printed no replay time for {n}:\n{out[-2000:]}")
            replay[n].append(float(m.group(1)))
            process[n].append(elapsed)
        print(f"round {round_ + 1}/{args.rounds} done", file=sys.stderr)

    print("| capture | tiler s | llvmpipe replay s | ratio | llvmpipe process s | ratio |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for n in names:
        t, r, p = (statistics.median(x[n]) for x in (tiler, replay, process))
        print(f"| {n} | {t:.3f} | {r:.3f} | {t / r:.2f} | {p:.3f} | {t / p:.2f} |")


if __name__ == "__main__":
    main()
