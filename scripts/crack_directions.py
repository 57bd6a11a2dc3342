"""Crack directions in a plate hit at its centre (issue 13), shared by
crack-directions.sh (one plate) and crack-directions-pooled.sh (many plates).

At the last frame, every damaged particle (damage >= 0.35) more than 3λ from the
impact point gets the direction of the crack through it: the principal axis, in the
plate's plane (x, y), of the damaged particles within 2.5λ of it, kept where that
cloud is elongated (eigenvalue ratio >= 4). Positions are read at the first frame,
where the cracks formed, not where the fragments flew."""
import math
import os

from cache_ply import particles as ply

LAMBDA = 0.016


def directions(cache, centre, lam=LAMBDA):
    """The crack directions (degrees, modulo 180, in the scene's x-y plane) of a cache."""
    frames = sorted(os.listdir(os.path.join(cache, 'particles')))
    first = ply(os.path.join(cache, 'particles', frames[0]))
    end = ply(os.path.join(cache, 'particles', frames[-1]))
    damaged = [(p['x'], p['y']) for p, q in zip(first, end) if q['damage'] >= 0.35]
    cell = 2.5 * lam
    grid = {}
    for i, (x, y) in enumerate(damaged):
        grid.setdefault((math.floor(x / cell), math.floor(y / cell)), []).append(i)
    found = []
    for (x, y) in damaged:
        if math.hypot(x - centre[0], y - centre[1]) < 3 * lam:
            continue
        cx, cy = math.floor(x / cell), math.floor(y / cell)
        near = [damaged[j] for a in (-1, 0, 1) for b in (-1, 0, 1)
                for j in grid.get((cx + a, cy + b), [])
                if math.hypot(damaged[j][0] - x, damaged[j][1] - y) <= cell]
        if len(near) < 6:
            continue
        mx = sum(p[0] for p in near) / len(near)
        my = sum(p[1] for p in near) / len(near)
        sxx = sum((p[0] - mx) ** 2 for p in near)
        syy = sum((p[1] - my) ** 2 for p in near)
        sxy = sum((p[0] - mx) * (p[1] - my) for p in near)
        tr, det = sxx + syy, sxx * syy - sxy * sxy
        root = math.sqrt(max(tr * tr / 4 - det, 0.0))
        big, small = tr / 2 + root, tr / 2 - root
        if small > 0 and big / small < 4:
            continue
        found.append(math.degrees(0.5 * math.atan2(2 * sxy, sxx - syy)) % 180.0)
    return found


def histogram(angles):
    """12 bins of 15° centred on 0°, 15°, ... 165°."""
    bins = [0] * 12
    for a in angles:
        bins[int(((a + 7.5) % 180.0) // 15.0)] += 1
    return bins


def peak(bins):
    """The largest bin over the mean (1 for a flat histogram)."""
    total = sum(bins)
    return max(bins) / (total / len(bins)) if total else float('nan')

