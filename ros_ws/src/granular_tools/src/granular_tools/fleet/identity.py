"""What makes a bag the same bag for a resumed fleet run: its size, modification time and a
hash of its index section.

A rosbag 2.0 file starts with "#ROSBAG V2.0\\n" and a bag header record whose field index_pos
gives the offset of the index (connection and chunk-info records), which runs to the end of the
file. Hashing that section reads kilobytes, not the gigabytes of a bag, and changes whenever a
message is added, removed or moved. A bag whose index_pos is 0 was never closed (its recording
was cut short) and one whose index_pos lies past its end was cut afterwards: both are refused
here, before any worker spends time on them.
"""
import hashlib
import os
import struct

MAGIC = b"#ROSBAG V2.0\n"
_BAG_HEADER_OP = 0x03
_HASH_BLOCK = 1 << 20  # bytes read at a time while hashing the index


class BagIdentityError(ValueError):
    """A bag whose index cannot be found; the message names the bag."""


def _header_fields(data, path):
    fields, offset = {}, 0
    while offset < len(data):
        if offset + 4 > len(data):
            raise BagIdentityError(f"{path}: the bag header is corrupt")
        (length,) = struct.unpack_from("<I", data, offset)
        field = data[offset + 4:offset + 4 + length]
        name, separator, value = field.partition(b"=")
        if not separator or len(field) != length:
            raise BagIdentityError(f"{path}: the bag header is corrupt")
        fields[name] = value
        offset += 4 + length
    return fields


def index_position(path):
    """The offset of the bag's index section; BagIdentityError when there is none."""
    try:
        with open(path, "rb") as stream:
            start = stream.read(len(MAGIC) + 4)
            if not start.startswith(MAGIC) or len(start) < len(MAGIC) + 4:
                raise BagIdentityError(f"{path}: not a rosbag 2.0 file")
            (header_length,) = struct.unpack_from("<I", start, len(MAGIC))
            if header_length > 4096:  # a bag header holds three short fields
                raise BagIdentityError(f"{path}: the bag header is corrupt")
            fields = _header_fields(stream.read(header_length), path)
    except OSError as error:
        raise BagIdentityError(f"{path}: cannot read bag: {error.strerror or error}") from error
    if fields.get(b"op") != bytes([_BAG_HEADER_OP]) or len(fields.get(b"index_pos", b"")) != 8:
        raise BagIdentityError(f"{path}: the bag header is corrupt")
    (position,) = struct.unpack("<Q", fields[b"index_pos"])
    size = os.path.getsize(path)
    if position == 0:
        raise BagIdentityError(f"{path}: the bag has no index (was its recording cut short?); "
                               f"'rosbag reindex {path}' may repair it")
    if position >= size:
        raise BagIdentityError(f"{path}: the bag is cut short: its index starts at byte "
                               f"{position} of a {size}-byte file")
    return position


def bag_identity(path):
    """{"size", "mtime_ns", "index_sha256"} of the bag at `path`; BagIdentityError when its
    index cannot be found."""
    position = index_position(path)
    digest = hashlib.sha256()
    try:
        with open(path, "rb") as stream:
            stream.seek(position)
            for block in iter(lambda: stream.read(_HASH_BLOCK), b""):
                digest.update(block)
            stat = os.fstat(stream.fileno())
    except OSError as error:
        raise BagIdentityError(f"{path}: cannot read bag: {error.strerror or error}") from error
    return {"size": stat.st_size, "mtime_ns": stat.st_mtime_ns,
            "index_sha256": digest.hexdigest()}
