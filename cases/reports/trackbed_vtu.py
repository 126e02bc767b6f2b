"""Reads the VTU files trackbed writes (VTK XML UnstructuredGrid, raw appended data with UInt64
headers, little endian; docs/formats.md) into numpy arrays, for the plotting scripts."""
import re

import numpy as np

_TYPES = {"Float64": np.float64, "Int64": np.int64, "UInt8": np.uint8}


def read_vtu(path):
    """Returns {"points": (n, 3) array, "point_data": {name: array}, "cell_data": {...}}."""
    with open(path, "rb") as f:
        raw = f.read()
    start = raw.index(b"<AppendedData")
    data = raw[raw.index(b"_", start) + 1:]
    header = raw[:start].decode("utf-8")
    out = {"points": None, "point_data": {}, "cell_data": {}}
    section = None
    for line in header.splitlines():
        if "<PointData" in line:
            section = "point_data"
        elif "<CellData" in line:
            section = "cell_data"
        elif "<Points>" in line or "<Cells>" in line:
            section = None
        m = re.search(r'<DataArray type="(\w+)" Name="([^"]+)" NumberOfComponents="(\d+)" '
                      r'format="appended" offset="(\d+)"', line)
        if not m:
            continue
        kind, name, comps, offset = m.group(1), m.group(2), int(m.group(3)), int(m.group(4))
        nbytes = int(np.frombuffer(data[offset:offset + 8], dtype="<u8")[0])
        values = np.frombuffer(data[offset + 8:offset + 8 + nbytes], dtype=_TYPES[kind])
        if comps > 1:
            values = values.reshape(-1, comps)
        if name == "Points":
            out["points"] = values
        elif section:
            out[section][name] = values
    return out
