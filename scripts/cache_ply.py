"""The particle frames of a perifrac cache (particles/NNNN.ply: binary little-endian,
one vertex element, float properties), read without dependencies, for the scripts
that measure caches (debris-speed.sh, crack-directions.sh, contact-bench.sh)."""
import struct


def particles(path):
    """Each particle of the frame at `path` as a dict of its properties."""
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + 11
    head = data[:end].decode().splitlines()
    n = int(next(l for l in head if l.startswith('element vertex')).split()[2])
    names = [l.split()[2] for l in head if l.startswith('property')]
    rows = struct.iter_unpack('<' + 'f' * len(names), data[end:end + 4 * len(names) * n])
    return [dict(zip(names, r)) for r in rows]
