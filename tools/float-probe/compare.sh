#!/bin/bash
# usage: compare.sh SHADER.frag W H [TILER]
# Runs float-probe on llvmpipe under apitrace, replays the capture with tiler (the pbuffer is
# its window; --snapshot at the glReadPixels call), and prints both sets of float bits with
# the pixels that differ marked. Needs apitrace and a float-probe built beside this script.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
frag=$1; w=$2; h=$3; tiler=${4:-tiler}
work=$(mktemp -d)
WAFFLE_PLATFORM=surfaceless_egl apitrace trace --api egl -o "$work/probe.trace" \
    "$here/float-probe" "$frag" "$w" "$h" > "$work/llvmpipe.txt" 2> "$work/record.log"
call=$(apitrace dump "$work/probe.trace" 2>/dev/null | awk '/glReadPixels/ {print $1}')
"$tiler" analyze "$work/probe.trace" --frames "$work/frames" --snapshot "$call" > "$work/tiler.log"
python3 - "$work" "$w" "$h" <<'PY'
import sys, struct, zlib
work, w, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def png_rgba(path):
    d = open(path, 'rb').read(); i = 8; idat = b''
    while i < len(d):
        n, = struct.unpack('>I', d[i:i+4]); t = d[i+4:i+8]; c = d[i+8:i+8+n]; i += 12 + n
        if t == b'IHDR': width, height, depth, kind = struct.unpack('>IIBB', c[:10])
        elif t == b'IDAT': idat += c
    assert depth == 8 and kind == 6, 'RGBA8 PNG expected'
    raw = zlib.decompress(idat); stride = width * 4; rows = []; prev = bytearray(stride); p = 0
    for _ in range(height):
        f = raw[p]; line = bytearray(raw[p+1:p+1+stride]); p += 1 + stride
        for x in range(stride):
            a = line[x-4] if x >= 4 else 0; b = prev[x]; c = prev[x-4] if x >= 4 else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return height, rows
import glob
height, rows = png_rgba(glob.glob(work + '/frames/call-*.png')[0])
ref = [l.split() for l in open(work + '/llvmpipe.txt').read().split('\n') if l.strip()]
f = lambda b: struct.unpack('>f', bytes.fromhex(b))[0]
differ = 0
for y in range(h):
    row = rows[height - 1 - y]
    ours = ['%02x%02x%02x%02x' % tuple(row[4*x:4*x+4]) for x in range(w)]
    for x in range(w):
        mark = '' if ours[x] == ref[y][x] else '  <- differs'
        differ += bool(mark)
        print(f'y={y} x={x}: llvmpipe {ref[y][x]} {f(ref[y][x]):.9g}  tiler {ours[x]} {f(ours[x]):.9g}{mark}')
print(f'{differ} of {w*h} differ')
PY
