"""Prints every attribute default and time sample of a USD layer, as Pixar's usd-core
reads it, as one JSON object {"/Prim.attribute": default, "/Prim.attribute@TIME": sample}
(TIME printed as Python's "%g"): numbers as numbers, vectors, quaternions
([real, i, j, k]) and matrices (row by row, flattened) as lists of numbers, tokens,
strings and asset paths as strings, time codes as numbers. usd/src/layer_arrays_test.rs
compares it with what our writer wrote.

usage: python usdc_defaults.py LAYER
"""

import json
import sys

from pxr import Gf, Sdf


def plain(value):
    """A JSON-able copy of a value read by Sdf."""
    if isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, Sdf.AssetPath):
        return value.path
    if isinstance(value, Gf.TimeCode):
        return value.GetValue()
    if isinstance(value, (Gf.Quath, Gf.Quatf, Gf.Quatd)):
        return [value.GetReal(), *value.GetImaginary()]
    if isinstance(value, (Gf.Matrix2d, Gf.Matrix3d, Gf.Matrix4d)):
        return [x for row in value for x in row]
    return [plain(x) for x in value]


def main():
    layer = Sdf.Layer.FindOrOpen(sys.argv[1])
    if layer is None:
        sys.exit(f"{sys.argv[1]}: usd-core cannot open it")
    defaults = {}

    def visit(path):
        attribute = layer.GetAttributeAtPath(path) if path.IsPropertyPath() else None
        if attribute is None:
            return
        if attribute.HasDefaultValue():
            defaults[str(path)] = plain(attribute.default)
        for time in layer.ListTimeSamplesForPath(path):
            defaults[f"{path}@{time:g}"] = plain(layer.QueryTimeSample(path, time))

    layer.Traverse(Sdf.Path.absoluteRootPath, visit)
    json.dump(defaults, sys.stdout)


main()
