"""Parses a ParaView .pvd with xml.etree and prints "root TYPE", then "dataset TIMESTEP FILE"
for every DataSet. Exits non-zero if the file is not well-formed XML."""
import sys
import xml.etree.ElementTree as ET

root = ET.parse(sys.argv[1]).getroot()
print(f"root {root.tag} {root.get('type')}")
for ds in root.iter("DataSet"):
    print(f"dataset {float(ds.get('timestep'))!r} {ds.get('file')}")
