"""Names, symbols and units of the particle fields as pictures show them: stresses in kPa,
everything else in the SI unit the run wrote (docs/post-processing.md lists the fields)."""

# field -> (description, symbol in matplotlib mathtext, SI unit); a symbol with a component
# takes it as a subscript (sigma_xx), `|symbol|` is the magnitude of a vector.
FIELDS = {
    "velocity": ("velocity", "v", "m/s"),
    "speed": ("speed", "|v|", "m/s"),
    "displacement": ("displacement", "u", "m"),
    "stress": ("stress", r"\sigma", "Pa"),
    "mean_stress_p": ("mean stress", "p", "Pa"),
    "deviatoric_stress_q": ("deviatoric stress", "q", "Pa"),
    "principal_stress": ("principal stress", r"\sigma", "Pa"),
    "principal_angle": ("direction of the larger principal stress", r"\theta", "°"),
    "relative_yield": ("relative yield", r"f_\mathrm{rel}", "-"),
    "smoothed_stress": ("smoothed stress", r"\bar\sigma", "Pa"),
    "smoothed_p": ("smoothed mean stress", r"\bar p", "Pa"),
    "smoothed_q": ("smoothed deviatoric stress", r"\bar q", "Pa"),
    "smoothed_principal_stress": ("smoothed principal stress", r"\bar\sigma", "Pa"),
    "smoothed_principal_angle": ("direction of the larger smoothed principal stress", r"\bar\theta", "°"),
    "smoothed_relative_yield": ("smoothed relative yield", r"\bar f_\mathrm{rel}", "-"),
    "volume": ("volume", "V", "m³/m"),
    "det_F": ("volume ratio", r"\det F", "-"),
    "F": ("deformation gradient", "F", "-"),
    "Fe": ("elastic deformation gradient", r"F^e", "-"),
    "Fp": ("plastic deformation gradient", r"F^p", "-"),
    "stress_from_Fe": ("stress from Fe", r"\sigma(F^e)", "Pa"),
    "engineering_strain": ("engineering strain", r"\varepsilon", "-"),
    "green_strain": ("Green strain", "E", "-"),
    "hencky_strain": ("Hencky strain", r"\ln U", "-"),
    "plastic_shear_strain": ("plastic shear strain", r"\gamma^p", "-"),
    "yielding": ("yielding", "", "0/1"),
    "material_id": ("material", "", "index"),
    "body_id": ("body", "", "index"),
}

# SI unit -> (unit shown, factor from SI)
DISPLAY = {"Pa": ("kPa", 1e-3)}


def unit_of(name, dim=2):
    """The SI unit of a field."""
    if name == "volume" and dim == 3:
        return "m³"
    if name in FIELDS:
        return FIELDS[name][2]
    if "stress" in name or name.endswith("_p") or name.endswith("_q"):
        return "Pa"
    return "-"


def display(name, dim=2):
    """(unit shown, factor from the SI values) of a field in a picture."""
    unit = unit_of(name, dim)
    return DISPLAY.get(unit, (unit, 1.0))


def label(name, component=None, dim=2):
    """Colour-bar label of a field, its component (a name such as xx or s1) or its magnitude
    (component "mag"): description, symbol and unit, e.g. "stress $\\sigma_{xx}$ [kPa]"."""
    what, symbol, _ = FIELDS.get(name, (name.replace("_", " "), "", ""))
    unit = display(name, dim)[0]
    if symbol and component == "mag":
        symbol = symbol if symbol.startswith("|") else f"|{symbol}|"
    elif symbol and component:
        sub = component[1:] if component.startswith("s") and component[1:].isdigit() else component
        symbol = f"{symbol}_{{{sub}}}" if not symbol.endswith("}") else f"{{{symbol}}}_{{{sub}}}"
    elif component and component != "mag":
        what += f" {component}"
    text = f"{what} ${symbol}$" if symbol else what
    return f"{text} [{unit}]"
