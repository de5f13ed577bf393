"""Reads Lopin's ParaView output with independent readers and prints one JSON object.

The .pvd collection is parsed with the standard library's XML parser; every .vtu is read by
meshio. Usage: vtu_probe.py RUN.pvd NODE CELL
"""

import json
import os
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np


def main():
    pvd, node, cell = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    root = ET.parse(pvd).getroot()
    sets = root.find("Collection").findall("DataSet")
    entries = [
        {"time": float(d.get("timestep")), "part": int(d.get("part")), "file": d.get("file")}
        for d in sets
    ]
    base = os.path.dirname(pvd)
    files = {}
    for e in entries:
        m = meshio.read(os.path.join(base, e["file"]))
        blocks = [(c.type, len(c.data)) for c in m.cells]
        pd = {k: np.asarray(v) for k, v in m.point_data.items()}
        cd = {k: np.concatenate([np.asarray(b).reshape(len(b), -1) for b in v]) for k, v in m.cell_data.items()}
        files[e["file"]] = {
            "points": int(len(m.points)),
            "cell_blocks": blocks,
            "point_data": sorted(pd),
            "cell_data": sorted(cd),
            "x": m.points[node].tolist(),
            "displacement": pd["displacement"][node].tolist(),
            "velocity": pd["velocity"][node].tolist(),
            "velocity_avg": pd["velocity_avg"][node].tolist(),
            "von_mises": cd["von_mises"][cell].tolist(),
            "stress": cd["stress"][cell].tolist(),
            "substructure": cd["substructure"][cell].tolist(),
            "material": cd["material"][cell].tolist(),
            "max_velocity": float(np.abs(pd["velocity"]).max()),
        }
    print(json.dumps({"entries": entries, "files": files}))


if __name__ == "__main__":
    main()
