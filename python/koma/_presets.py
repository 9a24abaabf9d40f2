"""Named presets: the request options each `preset=` stands for, as `koma --preset NAME`.

The same table as the CLI's (docs/usage.md, "Presets and studio defaults"); the Python tests
compare each preset's answer with the CLI's. Options given beside a preset win over it.
"""

SKELETAL = {
    "twos": {"drawings_per_second": 12.0},
    "threes": {"drawings_per_second": 8.0},
    "snappy": {"omissions_per_second": 1.5, "drawings_per_second": 8.0},
    "subtle": {"omissions_per_second": 0.5, "drawings_per_second": 12.0},
    # Naming a count turns the anime defaults off: the paper's 4 omissions, N / 3 holds and
    # on threes (docs/semantics.md, "Defaults: anime timing").
    "paper": {"max_hold": 3},
}

CURVES = {
    "twos": {"frames_per_drawing": 2},
    "threes": {"frames_per_drawing": 3},
    "snappy": {"frames_per_drawing": 3, "tame": 1.5, "tsume": 2.0},
    "subtle": {"frames_per_drawing": 2},
    "paper": {},
}

LIP_BLINK = {
    "twos": {"mouth": {"frames_per_shape": 2}},
    "threes": {"mouth": {"frames_per_shape": 3}},
    "snappy": {"mouth": {"frames_per_shape": 2}},
    "subtle": {"mouth": {"frames_per_shape": 3, "mode": "MOUTH_FOLLOW"}},
    "paper": {},
}


def apply(table, preset, options):
    """`options` over the preset's: a new dict (options that are None left out of it, so a
    preset's value stays). preset None: `options` as they are."""
    if preset is None:
        return dict(options)
    if preset not in table:
        raise ValueError(f"preset: {preset!r} is not one of {', '.join(table)}")
    merged = {key: (dict(value) if isinstance(value, dict) else value)
              for key, value in table[preset].items()}
    for key, value in options.items():
        if value is None:  # not given (the CLI's unset flags): the preset's stays
            continue
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key].update(value)
        elif key == "omissions" and "omissions_per_second" in merged:
            # A count given beside a preset's rate replaces it (as --omit on the CLI's line).
            del merged["omissions_per_second"]
            merged[key] = value
        else:
            merged[key] = value
    return merged
