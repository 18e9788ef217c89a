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
    """Body id -> name, in the order of the [[body]] tables (ids follow that order), then the
    dilated continua NAME_dilated (Paper III §C.3.2; [[body]] dilation_continuum, default on
    with [[contact]] for a deformable body whose material has max_void_ratio), in the same
    order, as src/scenario/parser_dilation.cpp adds them."""
    if not scenario:
        return {}
    bodies = scenario.get("body", [])
    names = {i: b.get("name", f"body-{i}") for i, b in enumerate(bodies)}
    materials = {m.get("name"): m for m in scenario.get("material", [])}
    contact = bool(scenario.get("contact"))
    for i, b in enumerate(bodies):
        m = materials.get(b.get("material"), {})
        cutoff = m.get("model") == "mohr-coulomb" and m.get("max_void_ratio", 0) > 0
        possible = cutoff and not b.get("rigid", False)
        if b.get("dilation_continuum", contact and possible) and possible:
            names[len(names)] = names[i] + "_dilated"
    return names


def body_names_of(outdir):
    return body_names(read_scenario(outdir)[1])
