"""Labels in file names, as granular_core/dataset/object_names.h writes them: every byte of the
UTF-8 label outside [A-Za-z0-9_.], and a leading '.', as '%' and two upper-case hex digits, so
that "Tram_/_Subway" names "Tram_%2F_Subway.pcd" and comes back exactly. Plain labels (Sedan,
SchoolBus) are unchanged."""
import re

# The label of an object no classifier has named (segments, geometric cuboids), as
# granular_core's kUnknownLabel.
UNKNOWN = "unknown"

_PLAIN = re.compile(rb"[A-Za-z0-9_.]")
_ESCAPE = re.compile(r"%([0-9A-F]{2})")


def _plain(byte, first):
    return bool(_PLAIN.fullmatch(bytes([byte]))) and not (first and byte == ord("."))


def encode_label(label):
    """The file-name form of `label` (str)."""
    out = []
    for i, byte in enumerate(label.encode("utf-8")):
        out.append(chr(byte) if _plain(byte, i == 0) else f"%{byte:02X}")
    return "".join(out)


def decode_label(encoded):
    """The label of a file-name form; None when encode_label could not have given it."""
    raw, i = bytearray(), 0
    while i < len(encoded):
        if encoded[i] == "%":
            match = _ESCAPE.match(encoded, i)
            if not match or _plain(int(match.group(1), 16), not raw):
                return None
            raw.append(int(match.group(1), 16))
            i += 3
            continue
        byte = ord(encoded[i])
        if byte > 127 or not _plain(byte, not raw):
            return None
        raw.append(byte)
        i += 1
    if not raw:
        return None
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return None


def model_label(path):
    """The class of a model file `<label>.pcd` (a pathlib.Path), or None."""
    return decode_label(path.stem)


def object_label(path):
    """The class of an object file `<label>-<stamp>-<index>.pcd` (a pathlib.Path), or None."""
    encoded, dash, _ = path.name.partition("-")
    return decode_label(encoded) if dash else None
