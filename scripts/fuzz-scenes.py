"""Fuzzes whole scenes through the CLI (docs/fuzz.md, "Whole scenes"): each shipped
scene in assets/scenes with one random edit (a number written over with 0, −1, 1e30,
nan, inf, a string or an array; a key's line deleted; a table header repeated),
written beside it so its relative paths hold, then `perifrac check` (or `perifrac run
--frames 1`) on it. Every mutant must end with exit code 0 or 2 within the timeout:
a panic (101), a signal or a hang is reported and its scene kept in OUT.

    python3 scripts/fuzz-scenes.py SEED MUTANTS_PER_SCENE [check|run] [OUT]
"""
import glob
import os
import random
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VALUES = ['0', '0.0', '-1.0', '1e30', '-1e-30', 'nan', 'inf', '-inf', '1e-12', '3.5e9', '2',
          '-0.0', '1e308', '"x"', '[]', '{}', 'true']
NUMBER = re.compile(r'(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?(?![\w.])')


def mutate(lines, rng):
    """One random edit of a scene's lines, or None when the scene offers none of the kind."""
    lines = list(lines)
    kind = rng.random()
    if kind < 0.7:
        spots = [(i, m) for i, line in enumerate(lines) if not line.lstrip().startswith('#')
                 for m in NUMBER.finditer(line.split('#')[0])]
        if not spots:
            return None
        i, m = rng.choice(spots)
        lines[i] = lines[i][:m.start()] + rng.choice(VALUES) + lines[i][m.end():]
    elif kind < 0.85:
        keys = [i for i, line in enumerate(lines) if '=' in line and not line.lstrip().startswith('#')]
        if not keys:
            return None
        del lines[rng.choice(keys)]
    else:
        tables = [i for i, line in enumerate(lines) if line.startswith('[')]
        if not tables:
            return None
        i = rng.choice(tables)
        lines.insert(i, lines[i])
    return '\n'.join(lines)


def main(seed, per_scene, command='check', out='out/fuzz-scenes'):
    rng = random.Random(seed)
    binary = os.path.join(ROOT, 'target/release/perifrac')
    os.makedirs(out, exist_ok=True)
    tried = bad = 0
    for path in sorted(glob.glob(os.path.join(ROOT, 'assets/scenes/*.toml'))):
        lines = open(path).read().split('\n')
        for k in range(per_scene):
            text = mutate(lines, rng)
            if text is None:
                continue
            mutant = os.path.join(os.path.dirname(path), '.fuzz-mutant.toml')
            open(mutant, 'w').write(text)
            args = [binary, 'check', mutant] if command == 'check' else \
                [binary, 'run', mutant, '-o', os.path.join(out, 'cache'), '--force', '--quiet',
                 '--frames', '1']
            try:
                code = subprocess.run(args, capture_output=True, timeout=60).returncode
            except subprocess.TimeoutExpired:
                code = 'timeout'
            finally:
                os.remove(mutant)
            tried += 1
            if code not in (0, 2):
                bad += 1
                kept = os.path.join(out, f'{os.path.basename(path)[:-5]}-{seed}-{k}.toml')
                open(kept, 'w').write(text)
                print(f'{code}: {kept}')
    print(f'{tried} mutants, {bad} ended otherwise than with exit code 0 or 2')


if __name__ == '__main__':
    main(int(sys.argv[1]), int(sys.argv[2]), *sys.argv[3:5])
