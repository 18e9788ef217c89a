"""Parses a JSON object with the json module and prints "KEY JSONVALUE" per key, the value
re-encoded with json.dumps (ASCII only). Exits non-zero if the file is not strict JSON."""
import json
import sys

with open(sys.argv[1], "rb") as f:
    raw = f.read()
obj = json.loads(raw.decode("utf-8"), parse_constant=lambda c: sys.exit(f"bad constant {c}"))
for key, value in obj.items():
    print(f"{key} {json.dumps(value)}")
