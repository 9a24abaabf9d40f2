"""Keyword options -> request message fields, checked against the proto's own descriptors.

Option names are the proto field names (omissions, max_hold, timing_fps, ...); nested
messages are dicts with their fields' names (mouth={"ids": [...], "mode": "MOUTH_FOLLOW"}),
enums take their value name ("TIMING_RATE") or number. A wrong name or type raises here,
before any call; a value out of range comes back from the server as a KomaError naming the
field (the server owns the rules, so client and server never disagree about them).
"""
import numbers

from google.protobuf.descriptor import FieldDescriptor

_INTEGER_TYPES = {
    FieldDescriptor.TYPE_INT32: (-(1 << 31), (1 << 31) - 1),
    FieldDescriptor.TYPE_INT64: (-(1 << 63), (1 << 63) - 1),
    FieldDescriptor.TYPE_UINT32: (0, (1 << 32) - 1),
    FieldDescriptor.TYPE_UINT64: (0, (1 << 64) - 1),
}
_FLOAT_TYPES = (FieldDescriptor.TYPE_DOUBLE, FieldDescriptor.TYPE_FLOAT)


def _scalar(field, value, path):
    """`value` checked and converted for the scalar `field`."""
    if field.type in _INTEGER_TYPES:
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise TypeError(f"{path}: expected an integer, got {value!r}")
        low, high = _INTEGER_TYPES[field.type]
        if not low <= value <= high:
            raise ValueError(f"{path}: {value} does not fit the field ({low}..{high})")
        return int(value)
    if field.type in _FLOAT_TYPES:
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise TypeError(f"{path}: expected a number, got {value!r}")
        return float(value)
    if field.type == FieldDescriptor.TYPE_BOOL:
        if not isinstance(value, bool):
            raise TypeError(f"{path}: expected True or False, got {value!r}")
        return value
    if field.type == FieldDescriptor.TYPE_STRING:
        if not isinstance(value, str):
            raise TypeError(f"{path}: expected a string, got {value!r}")
        return value
    if field.type == FieldDescriptor.TYPE_ENUM:
        names = [v.name for v in field.enum_type.values if v.number != 0]
        if isinstance(value, str):
            if value not in field.enum_type.values_by_name:
                raise ValueError(f"{path}: {value!r} is not one of {', '.join(names)}")
            return field.enum_type.values_by_name[value].number
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or \
                value not in field.enum_type.values_by_number:
            raise ValueError(f"{path}: {value!r} is not one of {', '.join(names)}")
        return int(value)
    raise TypeError(f"{path}: unsupported field type")


def _message(message, value, path):
    """Fills the sub-message `message` from a dict (or, for a FrameInterval, a pair)."""
    if message.DESCRIPTOR.name == "FrameInterval" and isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise ValueError(f"{path}: expected (begin, end), got {value!r}")
        value = {"begin": value[0], "end": value[1]}
    if not isinstance(value, dict):
        raise TypeError(f"{path}: expected a dict of {message.DESCRIPTOR.name} fields, "
                        f"got {value!r}")
    fill(message, value, path + ".")


def fill(message, options, prefix="", skip=()):
    """Sets `message`'s fields from `options` (name -> value); None leaves a field unset."""
    fields = message.DESCRIPTOR.fields_by_name
    for name, value in options.items():
        path = prefix + name
        field = fields.get(name)
        if field is None or name in skip:
            known = sorted(n for n in fields if n not in skip)
            raise TypeError(f"unknown option {path!r} for {message.DESCRIPTOR.name}; known: "
                            f"{', '.join(known)}")
        if value is None:
            continue
        if field.label == FieldDescriptor.LABEL_REPEATED:
            if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
                raise TypeError(f"{path}: expected a list, got {value!r}")
            target = getattr(message, name)
            for i, item in enumerate(value):
                if field.type == FieldDescriptor.TYPE_MESSAGE:
                    _message(target.add(), item, f"{path}[{i}]")
                else:
                    target.append(_scalar(field, item, f"{path}[{i}]"))
        elif field.type == FieldDescriptor.TYPE_MESSAGE:
            _message(getattr(message, name), value, path)
        else:
            setattr(message, name, _scalar(field, value, path))

