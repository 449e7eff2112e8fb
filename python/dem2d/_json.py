"""Case dicts to JSON text, exactly: Python writes a float as the shortest text that reads back
to the same double, and dem2d reads the double nearest to the text, so every number survives the
round trip bit for bit."""

import json


def _default(value):
    # numpy arrays and numpy scalars (np.int64, np.bool_ are not JSON's own types).
    tolist = getattr(value, "tolist", None)
    if tolist is not None:
        return tolist()
    raise TypeError(
        f"{type(value).__name__} is not a case value (give numbers, strings, booleans, lists, "
        "dicts or numpy arrays)"
    )


def dumps(spec):
    """The JSON text of a case dict (indented; NaN and Infinity written as such, so that dem2d
    refuses them naming the field)."""
    return json.dumps(spec, indent=2, allow_nan=True, default=_default, ensure_ascii=False) + "\n"
