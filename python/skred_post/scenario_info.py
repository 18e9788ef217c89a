"""The scenario copied into the output folder (scenario.toml), read with Python's tomllib."""
import os
import tomllib


def read_scenario(outdir):
    """(text, parsed dict) of OUTDIR/scenario.toml; (None, None) if absent, (text, None) if
    it does not parse."""
    path = os.path.join(outdir, "scenario.toml")
    if not os.path.isfile(path):
        return None, None
    with open(path, encoding="utf-8") as f:
        text = f.read()
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return text, None


def body_names(scenario):
    """Body id -> name, in the order of the [[body]] tables (ids follow that order)."""
    if not scenario:
        return {}
    return {i: b.get("name", f"body-{i}") for i, b in enumerate(scenario.get("body", []))}


def body_names_of(outdir):
    return body_names(read_scenario(outdir)[1])
