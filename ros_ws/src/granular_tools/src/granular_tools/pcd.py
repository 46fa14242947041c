"""The PCD file format: a sensor_msgs/PointCloud2 written as a binary PCD with every field of
the cloud, and a PCD file (binary or ascii) read back as structured points."""
import numpy as np
from sensor_msgs.msg import PointField

# PointField datatype -> (PCD TYPE, SIZE, numpy type)
_PCD_TYPES = {
    PointField.INT8: ("I", 1, "i1"), PointField.UINT8: ("U", 1, "u1"),
    PointField.INT16: ("I", 2, "<i2"), PointField.UINT16: ("U", 2, "<u2"),
    PointField.INT32: ("I", 4, "<i4"), PointField.UINT32: ("U", 4, "<u4"),
    PointField.FLOAT32: ("F", 4, "<f4"), PointField.FLOAT64: ("F", 8, "<f8"),
}


_DATATYPES = {(pcd_type, size): datatype for datatype, (pcd_type, size, _) in _PCD_TYPES.items()}


class CloudError(ValueError):
    """A cloud that cannot be written as a PCD; the message says why."""


def cloud_to_pcd(cloud):
    """The PCD file content (bytes) of a PointCloud2, fields in offset order, DATA binary."""
    fields = sorted(cloud.fields, key=lambda f: f.offset)
    names = [f.name for f in fields]
    missing = [axis for axis in "xyz" if axis not in names]
    if missing:
        raise CloudError(f"cloud has no {'/'.join(missing)} field (fields: {' '.join(names)})")
    if cloud.is_bigendian:
        raise CloudError("big-endian clouds are not supported")
    unknown = [f.name for f in fields if f.datatype not in _PCD_TYPES]
    if unknown:
        raise CloudError(f"fields with unknown datatype: {' '.join(unknown)}")
    count = cloud.width * cloud.height
    if len(cloud.data) < cloud.row_step * cloud.height or cloud.row_step < cloud.width * cloud.point_step:
        raise CloudError(f"cloud data holds {len(cloud.data)} bytes, too few for "
                         f"{cloud.height} rows of {cloud.row_step} bytes")
    types = [(f.name, _PCD_TYPES[f.datatype][2], (f.count,) if f.count > 1 else ())
             for f in fields]
    strided = np.dtype({"names": names, "formats": [np.dtype((t, s)) for _, t, s in types],
                        "offsets": [f.offset for f in fields], "itemsize": cloud.point_step})
    rows = np.frombuffer(cloud.data, dtype=np.uint8, count=cloud.row_step * cloud.height)
    rows = rows.reshape(cloud.height, cloud.row_step)[:, :cloud.width * cloud.point_step]
    points = np.ascontiguousarray(rows).view(strided).reshape(count)
    packed = np.empty(count, dtype=np.dtype([(n, t, s) for n, t, s in types]))
    for name in names:
        packed[name] = points[name]
    header = "\n".join([
        "# .PCD v0.7 - Point Cloud Data file format",
        "VERSION 0.7",
        "FIELDS " + " ".join(names),
        "SIZE " + " ".join(str(_PCD_TYPES[f.datatype][1]) for f in fields),
        "TYPE " + " ".join(_PCD_TYPES[f.datatype][0] for f in fields),
        "COUNT " + " ".join(str(max(f.count, 1)) for f in fields),
        f"WIDTH {cloud.width}",
        f"HEIGHT {cloud.height}",
        "VIEWPOINT 0 0 0 1 0 0 0",
        f"POINTS {count}",
        "DATA binary",
    ]) + "\n"
    return header.encode("ascii") + packed.tobytes()


def read_pcd(path):
    """Read a PCD file (DATA binary or ascii): (PointFields, structured points, width, height)."""
    with open(path, "rb") as stream:
        raw = stream.read()
    header, offset = {}, 0
    while "DATA" not in header:
        end = raw.find(b"\n", offset)
        if end < 0:
            raise CloudError(f"{path}: PCD header has no DATA line")
        line = raw[offset:end].decode("ascii", "replace").strip()
        offset = end + 1
        if line and not line.startswith("#"):
            key, _, value = line.partition(" ")
            header[key] = value.split()
    try:
        names = header["FIELDS"]
        sizes, types = [int(s) for s in header["SIZE"]], header["TYPE"]
        counts = [int(c) for c in header.get("COUNT", ["1"] * len(names))]
        width, height = int(header["WIDTH"][0]), int(header["HEIGHT"][0])
        fields, cursor = [], 0
        for name, size, pcd_type, count in zip(names, sizes, types, counts):
            fields.append(PointField(name, cursor, _DATATYPES[(pcd_type, size)], count))
            cursor += size * count
    except (KeyError, ValueError, IndexError) as error:
        raise CloudError(f"{path}: malformed PCD header ({error})") from error
    dtype = np.dtype([(f.name, _PCD_TYPES[f.datatype][2], (f.count,) if f.count > 1 else ())
                      for f in fields])
    count = width * height
    if header["DATA"][0] == "binary":
        if len(raw) - offset < count * dtype.itemsize:
            raise CloudError(f"{path}: {count} points announced, file is shorter")
        points = np.frombuffer(raw, dtype=dtype, count=count, offset=offset)
    elif header["DATA"][0] == "ascii":
        lines = raw[offset:].decode("ascii").splitlines()[:count]
        columns = np.loadtxt(lines, ndmin=2) if count else np.zeros((0, sum(counts)))
        if columns.shape != (count, sum(counts)):
            raise CloudError(f"{path}: {count} points of {sum(counts)} values announced, "
                             f"found {columns.shape[0]} rows of {columns.shape[1]}")
        points = np.zeros(count, dtype=dtype)
        column = 0
        for f in fields:
            points[f.name] = columns[:, column] if f.count == 1 else \
                columns[:, column:column + f.count]
            column += f.count
    else:
        raise CloudError(f"{path}: DATA {header['DATA'][0]} is not supported")
    return fields, points, width, height

