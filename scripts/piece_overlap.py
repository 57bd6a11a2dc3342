"""How deep a shot's pieces interpenetrate at a frame (docs/rigid.md, "No two pieces
overlapping by more than λ/2"): for every two tets of different fragments whose boxes
meet in tets/NNNN.vtu, their depth of interpenetration by the separating axis theorem
(each tet's face normals and the cross products of their edges), as the test
`a_dropped_glass_plate_shatters_and_every_piece_comes_to_rest` reads it. Prints the
deepest pairs and how many touch. Needs the cache's tets (`[output] tets = true`, or
`surface = "embedded"`) and particles.

    python3 scripts/piece_overlap.py OUT 0151
"""
import math
import os
import re
import struct
import sys

sys.path.insert(0, os.path.dirname(__file__))
from cache_ply import particles  # noqa: E402

EDGES = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]


def read_vtu(path):
    """The appended raw arrays of a perifrac tets/NNNN.vtu by name."""
    data = open(path, 'rb').read()
    head = data[:data.index(b'<AppendedData')].decode()
    start = data.index(b'_', data.index(b'<AppendedData')) + 1
    kinds = {'Int32': 'i', 'UInt32': 'I', 'Float32': 'f', 'Float64': 'd', 'UInt8': 'B'}
    arrays = {}
    pattern = r'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="\d+" ' \
              r'format="appended" offset="(\d+)"'
    for kind, name, offset in re.findall(pattern, head):
        at = start + int(offset)
        size = struct.unpack('<Q', data[at:at + 8])[0]
        code = kinds[kind]
        arrays[name] = struct.unpack('<%d%s' % (size // struct.calcsize(code), code),
                                     data[at + 8:at + 8 + size])
    return arrays


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def overlap(a, b):
    """Depth (m) to which tets a and b (four corners each) interpenetrate, 0 if apart."""
    axes = []
    for t in (a, b):
        for i, j, k in [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]:
            axes.append(cross(sub(t[j], t[i]), sub(t[k], t[i])))
    for i, j in EDGES:
        for k, l in EDGES:
            e, f = sub(a[j], a[i]), sub(b[l], b[k])
            n = cross(e, f)
            if dot(n, n) > 1e-12 * dot(e, e) * dot(f, f):
                axes.append(n)
    depth = math.inf
    for n in axes:
        pa = [dot(p, n) for p in a]
        pb = [dot(p, n) for p in b]
        o = min(max(pa) - min(pb), max(pb) - min(pa))
        if o <= 0:
            return 0.0
        depth = min(depth, o / math.sqrt(dot(n, n)))
    return depth


def main(out, frame):
    tets = read_vtu(f'{out}/tets/{frame}.vtu')
    points, conn, particle = tets['Points'], tets['connectivity'], tets['particle']
    fragment = [int(p['fragment']) for p in particles(f'{out}/particles/{frame}.ply')]
    size = {}
    for f in fragment:
        size[f] = size.get(f, 0) + 1
    corners = [[points[3 * conn[4 * t + k]:3 * conn[4 * t + k] + 3] for k in range(4)]
               for t in range(len(particle))]
    boxes = [([min(p[k] for p in c) for k in range(3)], [max(p[k] for p in c) for k in range(3)])
             for c in corners]
    order = sorted(range(len(corners)), key=lambda t: boxes[t][0][0])
    found = []
    for n, i in enumerate(order):
        for j in order[n + 1:]:
            if boxes[j][0][0] > boxes[i][1][0]:
                break
            fi, fj = fragment[particle[i]], fragment[particle[j]]
            meet = all(boxes[j][0][k] <= boxes[i][1][k] and boxes[i][0][k] <= boxes[j][1][k]
                       for k in (1, 2))
            if fi != fj and meet:
                d = overlap(corners[i], corners[j])
                if d > 0:
                    found.append((d, fi, fj))
    found.sort(reverse=True)
    print(f'{out} frame {frame}: {len(found)} pairs of tets of two fragments touch')
    for d, fi, fj in found[:10]:
        print(f'  {1000 * d:.2f} mm: fragments {fi} and {fj} ({size[fi]} and {size[fj]} particles)')


if __name__ == '__main__':
    main(sys.argv[1], sys.argv[2])
