#!/bin/sh
# Remakes the ASTC test files (Debian's astcenc 4.2.0): the pattern encoded at every 2D
# footprint with the exhaustive search, and astcenc's own decode of each (the reference).
set -e
cd "$(dirname "$0")"
python3 pattern.py
for f in 4x4 5x4 5x5 6x5 6x6 8x5 8x6 8x8 10x5 10x6 10x8 10x10 12x10 12x12; do
    astcenc -cl pattern.png "pattern-$f.astc" "$f" -exhaustive -silent
    astcenc -dl "pattern-$f.astc" "decoded-$f.png" -silent
done
rm pattern.png
