#!/usr/bin/env python3
"""Writes the elevation rasters of examples/valley_slope_3d.toml: a valley side 12 m high whose
fall line points 30 degrees north of east, with a shallow gully down it, a clay mantle 3 m thick
on a firm base. ESRI ASCII grids on 2 m cells, north up, in map coordinates (a UTM-like
easting and northing) around the scenario's footprint, with the scenario's mapping
([ground] origin and rotation) inverted to evaluate the shapes below at each cell centre.

    python3 examples/valley_slope_3d/make_rasters.py   # rewrites the .asc files beside it
"""
import math
import os

ORIGIN = (500000.0, 6100000.0)  # [ground] origin: the map point of scenario x = z = 0
ROTATION = math.radians(30.0)   # [ground] rotation: +x 30 degrees north of east
CELL = 2.0
HERE = os.path.dirname(os.path.abspath(__file__))


def surface(x, z):
    """The ground: a plateau at 16 m, a 0.75 slope (37 degrees) down to the valley floor at 4 m,
    and a gully 1.5 m deep across the slope, centred at z = 8."""
    y = 16.0 if x < 12.0 else 4.0 if x > 28.0 else 16.0 - 0.75 * (x - 12.0)
    if 10.0 < x < 30.0:
        y -= 1.5 * math.exp(-((z - 8.0) / 4.0) ** 2) * math.sin(math.pi * (x - 10.0) / 20.0)
    return y


def clay_base(x, z):
    return surface(x, z) - 3.0


def scenario_xz(e, n):
    """The inverse of map = origin + x e_x + z e_z (e_x at ROTATION from east, e_z a right angle
    clockwise from it)."""
    de, dn = e - ORIGIN[0], n - ORIGIN[1]
    c, s = math.cos(ROTATION), math.sin(ROTATION)
    return de * c + dn * s, de * s - dn * c


def write_asc(name, height):
    # The grid's footprint, x in [0, 48] and z in [0, 16], on the map, and a cell around it.
    corners = [(x, z) for x in (0.0, 48.0) for z in (0.0, 16.0)]
    c, s = math.cos(ROTATION), math.sin(ROTATION)
    es = [ORIGIN[0] + x * c + z * s for x, z in corners]
    ns = [ORIGIN[1] + x * s - z * c for x, z in corners]
    e0, n0 = math.floor(min(es) / CELL) * CELL - CELL, math.floor(min(ns) / CELL) * CELL - CELL
    cols = int(math.ceil((max(es) - e0) / CELL)) + 1
    rows = int(math.ceil((max(ns) - n0) / CELL)) + 1
    with open(os.path.join(HERE, name), "w") as out:
        out.write(f"ncols {cols}\nnrows {rows}\nxllcorner {e0}\nyllcorner {n0}\ncellsize {CELL}\n"
                  "NODATA_value -9999\n")
        for r in range(rows):
            n = n0 + (rows - r - 0.5) * CELL
            row = []
            for col in range(cols):
                x, z = scenario_xz(e0 + (col + 0.5) * CELL, n)
                # Beyond the footprint the shape goes on (clamped to it): whole cells at its edge.
                row.append(f"{height(min(max(x, 0.0), 48.0), min(max(z, 0.0), 16.0)):.3f}")
            out.write(" ".join(row) + "\n")


write_asc("surface.asc", surface)
write_asc("clay_base.asc", clay_base)
