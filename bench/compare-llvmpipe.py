#!/usr/bin/env python3
"""tiler against Mesa's llvmpipe on the benchmark scenes of SCENES.md, in one session.

Runs `tiler bench` and the peer harness (`../shared/peers/llvmpipe_bench.py`) on the same
scenes, interleaved run by run so that both see the same machine, and prints the table of
issue 8: median ms per frame of each, and the ratio llvmpipe / tiler against its target.
Every scene's pictures are held against each other with the reference tolerance (99% of pixels
within 8/255 per channel, `tiler diff`), so a speed-up never comes from doing less work.

    cargo build --release
    python3 bench/compare-llvmpipe.py --peer /path/to/peers     # the whole table
    python3 bench/compare-llvmpipe.py --only clear helmet --reps 1
    python3 bench/compare-llvmpipe.py --scaling                # also tiler on 1 thread

The peer needs Mesa and a Python venv: copy `../shared/peers` somewhere writable and run its
`setup.sh` there (see docs/benchmarking.md). Only the standard library is used here.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# name, tiler bench arguments, peer arguments (paths relative to the assets folder marked
# {assets}), frames, target ratio llvmpipe / tiler (issue 8).
SCENES = [
    ("clear", ["--scene", "clear"], ["--scene", "clear"], 200, 2.0),
    ("clear_msaa4", ["--scene", "clear", "--msaa", "4"], ["--scene", "clear", "--msaa", "4"], 50, 20.0),
    ("helmet", ["--scene", "helmet"],
     ["--scene", "gltf", "--gltf", "{assets}/DamagedHelmet/DamagedHelmet.gltf"], 20, 2.0),
    ("helmet_msaa4", ["--scene", "helmet", "--msaa", "4"],
     ["--scene", "gltf", "--msaa", "4", "--gltf", "{assets}/DamagedHelmet/DamagedHelmet.gltf"], 10, 4.0),
    ("atrium", ["--scene", "atrium"], ["--scene", "gltf", "--gltf", "{assets}/Atrium/Atrium.gltf"], 10, 2.0),
    ("overdraw", ["--scene", "overdraw", "--backend", "tbdr"], ["--scene", "overdraw", "--layers", "32"], 10, 20.0),
    ("overdraw_f2b", ["--scene", "overdraw_f2b"],
     ["--scene", "overdraw", "--layers", "32", "--order", "front-to-back"], 10, None),
    ("tris", ["--scene", "tris"], ["--scene", "tris", "--tris", "1000000"], 10, 2.0),
]


def run(cmd, env=None):
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p.stdout


def tiler_run(tiler, args, frames, size, threads, out_dir):
    cmd = [tiler, "bench", *args, "--frames", str(frames), "--size", size, "--threads", str(threads), "--json"]
    if out_dir:
        cmd += ["--out", out_dir]
    report = json.loads(run(cmd))
    result = report["results"][0]
    return result["median_ms"], os.path.join(out_dir, result["scene"] + ".png") if out_dir else None


def peer_run(python, peer, args, frames, size, threads, png):
    width, height = size.split("x")
    cmd = [python, os.path.join(peer, "llvmpipe_bench.py"), *args, "--frames", str(frames),
           "--width", width, "--height", height]
    if png:
        cmd += ["--out", png]
    out = run(cmd, env=dict(os.environ, LP_NUM_THREADS=str(threads)))
    line = [ln for ln in out.splitlines() if ln.startswith("JSON ")][-1]
    return json.loads(line[5:])["median_ms"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--peer", default=os.environ.get("TILER_PEER", os.path.join(ROOT, "..", "shared", "peers")),
                    help="the folder of llvmpipe_bench.py, set up with its setup.sh [default: $TILER_PEER, "
                         "else ../shared/peers]")
    ap.add_argument("--assets", default=os.environ.get("TILER_ASSETS", os.path.join(ROOT, "..", "shared", "assets")),
                    help="the glTF models [default: $TILER_ASSETS, else ../shared/assets]")
    ap.add_argument("--tiler", default=os.path.join(ROOT, "target", "release", "tiler"),
                    help="the tiler binary [default: target/release/tiler; build it with cargo build --release]")
    ap.add_argument("--only", nargs="*", help="scene names (default: all)")
    ap.add_argument("--reps", type=int, default=3, help="interleaved runs of each side per scene")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--threads", type=int, default=2, help="threads of both renderers")
    ap.add_argument("--scaling", action="store_true", help="also time tiler on one thread: the 1 → 2 speed-up")
    ap.add_argument("--frames", type=float, default=1.0, help="scale every scene's frame count")
    ap.add_argument("--out", default=None, help="keep the pictures and difference images here")
    ap.add_argument("--json", action="store_true", help="print the results as JSON")
    args = ap.parse_args()

    if not os.access(args.tiler, os.X_OK):
        sys.exit(f"{args.tiler}: not found; run `cargo build --release` first (or pass --tiler)")
    peer = os.path.abspath(args.peer)
    if not os.path.exists(os.path.join(peer, "llvmpipe_bench.py")):
        sys.exit(f"{peer}: no llvmpipe_bench.py; pass --peer (see docs/benchmarking.md)")
    venv = os.path.join(peer, ".venv", "bin", "python")
    python = venv if os.access(venv, os.X_OK) else sys.executable
    # The peer's Atrium is generated by its setup.sh into its own assets folder.
    assets = os.path.abspath(args.assets)
    out_dir = os.path.abspath(args.out) if args.out else tempfile.mkdtemp(prefix="tiler-vs-llvmpipe-")
    os.makedirs(out_dir, exist_ok=True)

    rows = []
    for name, tiler_args, peer_args, frames, target in SCENES:
        if args.only and name not in args.only:
            continue
        frames = max(1, int(frames * args.frames))
        peer_assets = os.path.join(peer, "assets") if "Atrium" in " ".join(peer_args) and \
            os.path.exists(os.path.join(peer, "assets", "Atrium")) else assets
        peer_args = [a.replace("{assets}", peer_assets) for a in peer_args]
        tiler_args = tiler_args + ["--assets", assets]
        tiler_ms, peer_ms, tiler_one = [], [], []
        tiler_png = peer_png = None
        try:
            for rep in range(args.reps):
                keep = rep == 0
                ms, png = tiler_run(args.tiler, tiler_args, frames, args.size, args.threads,
                                    os.path.join(out_dir, "tiler") if keep else None)
                tiler_ms.append(ms)
                tiler_png = png or tiler_png
                if keep:
                    peer_png = os.path.join(out_dir, "llvmpipe", name + ".png")
                    os.makedirs(os.path.dirname(peer_png), exist_ok=True)
                peer_ms.append(peer_run(python, peer, peer_args, frames, args.size, args.threads,
                                        peer_png if keep else None))
                if args.scaling:
                    tiler_one.append(tiler_run(args.tiler, tiler_args, frames, args.size, 1, None)[0])
        except RuntimeError as e:
            print(f"{name}: skipped: {e}", file=sys.stderr)
            continue
        diff_png = os.path.join(out_dir, name + ".diff.png")
        diff = subprocess.run([args.tiler, "diff", tiler_png, peer_png, "--out", diff_png],
                              capture_output=True, text=True)
        row = {
            "scene": name,
            "tiler_ms": statistics.median(tiler_ms),
            "llvmpipe_ms": statistics.median(peer_ms),
            "target": target,
            "picture": diff.stdout.strip() or diff.stderr.strip(),
            "pictures_match": diff.returncode == 0,
            "tiler_runs_ms": tiler_ms,
            "llvmpipe_runs_ms": peer_ms,
        }
        row["ratio"] = row["llvmpipe_ms"] / row["tiler_ms"]
        if tiler_one:
            row["tiler_1_thread_ms"] = statistics.median(tiler_one)
            row["scaling"] = row["tiler_1_thread_ms"] / row["tiler_ms"]
        rows.append(row)
        if not args.json:
            print_row(row, header=len(rows) == 1, scaling=args.scaling)

    if args.json:
        print(json.dumps({"size": args.size, "threads": args.threads, "reps": args.reps, "rows": rows}, indent=2))
    else:
        print(f"\npictures and difference images: {out_dir}")
    if any(not r["pictures_match"] for r in rows):
        sys.exit("some pictures differ from llvmpipe's beyond the reference tolerance (see above)")


def print_row(row, header, scaling):
    if header:
        cols = f"{'scene':<14} {'llvmpipe ms':>12} {'tiler ms':>10} {'ratio':>7} {'target':>7}"
        if scaling:
            cols += f" {'1 thread':>9} {'1→2':>6}"
        print(cols + "  picture")
    target = f"≥{row['target']:g}×" if row["target"] else "—"
    mark = "" if not row["target"] else (" ok" if row["ratio"] >= row["target"] else " short")
    line = (f"{row['scene']:<14} {row['llvmpipe_ms']:>12.2f} {row['tiler_ms']:>10.2f} "
            f"{row['ratio']:>6.2f}× {target:>7}{mark:<6}")
    if scaling:
        line += f" {row['tiler_1_thread_ms']:>9.2f} {row['scaling']:>5.2f}×"
    print(line + "  " + ("match" if row["pictures_match"] else "DIFFERENT: ") +
          ("" if row["pictures_match"] else row["picture"]), flush=True)


if __name__ == "__main__":
    main()
