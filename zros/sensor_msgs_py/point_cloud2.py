"""sensor_msgs/PointCloud2 <-> numpy, with the functions of ROS 2's sensor_msgs_py.point_cloud2.

A cloud's `data` is `width * height` records of `point_step` bytes, laid out by its PointFields.
`dtype_from_fields` turns the fields into a numpy structured dtype over exactly that layout, so
reading a cloud is one view of its buffer (no loop per point) and writing one is one copy.

    points = read_points_numpy(cloud, field_names=('x', 'y', 'z'), skip_nans=True)  # (N, 3)
    cloud = create_cloud_xyz32(header, points)
"""
from __future__ import annotations

from collections import namedtuple
from typing import Any, Iterable, NamedTuple, Sequence

import numpy as np

from interfaces.sensor_msgs.msg import PointCloud2, PointField

__all__ = ['read_points', 'read_points_numpy', 'read_points_list', 'create_cloud', 'create_cloud_xyz32',
           'dtype_from_fields', 'DUMMY_FIELD_PREFIX']

#: PointField datatype constant -> numpy type.
_DATATYPES = {
    PointField.INT8: np.dtype(np.int8), PointField.UINT8: np.dtype(np.uint8),
    PointField.INT16: np.dtype(np.int16), PointField.UINT16: np.dtype(np.uint16),
    PointField.INT32: np.dtype(np.int32), PointField.UINT32: np.dtype(np.uint32),
    PointField.FLOAT32: np.dtype(np.float32), PointField.FLOAT64: np.dtype(np.float64),
}
#: Name given to a field whose name is empty: `unnamed_field_<index>`.
DUMMY_FIELD_PREFIX = 'unnamed_field'


def dtype_from_fields(fields: Iterable[Any], point_step: int | None = None, *, big_endian: bool = False) -> np.dtype:
    """The structured dtype of one point. A field with `count` > 1 becomes `count` subfields
    named `<name>_0` ... `<name>_<count-1>`.

    Raises:
        ValueError: an unknown datatype, a count of 0 or a repeated name.
    """
    names, formats, offsets = [], [], []
    order = '>' if big_endian else '<'
    for index, field in enumerate(fields):
        base = _DATATYPES.get(field.datatype)
        if base is None:
            raise ValueError(f"PointField '{field.name}' has unknown datatype {field.datatype}")
        if field.count < 1:
            raise ValueError(f"PointField '{field.name}' has count 0")
        name = field.name or f'{DUMMY_FIELD_PREFIX}_{index}'
        for sub in range(field.count):
            subname = f'{name}_{sub}' if field.count > 1 else name
            if subname in names:
                raise ValueError(f"duplicate PointField name '{subname}'")
            names.append(subname)
            formats.append(base.newbyteorder(order))
            offsets.append(field.offset + sub * base.itemsize)
    spec: dict[str, Any] = {'names': names, 'formats': formats, 'offsets': offsets}
    if point_step is not None:
        spec['itemsize'] = point_step
    return np.dtype(spec)


def _data_bytes(data: Any) -> np.ndarray:
    if isinstance(data, (list, tuple)):
        return np.asarray(data, dtype=np.uint8)
    return np.frombuffer(data, dtype=np.uint8)


def read_points(cloud: Any, field_names: Sequence[str] | None = None, skip_nans: bool = False,
                uvs: Iterable | None = None, reshape_organized_cloud: bool = False) -> np.ndarray:
    """The cloud's points as a structured array (a view of the message's buffer when possible).

    Args:
        field_names: the fields to keep (all when None).
        skip_nans: drop points with a NaN in any kept float field (unless the cloud is dense).
        uvs: only these points: flat indices, or (u, v) pixel pairs of an organized cloud.
        reshape_organized_cloud: shape (width, height) for a cloud with height > 1, as in ROS 2.

    Raises:
        TypeError: `cloud` is not a sensor_msgs/PointCloud2.
        ValueError: a requested field does not exist, or data is shorter than the fields say.
    """
    if not isinstance(cloud, PointCloud2):
        raise TypeError(f'expected a sensor_msgs/msg/PointCloud2, got {type(cloud).__name__}')
    dtype = dtype_from_fields(cloud.fields, point_step=cloud.point_step, big_endian=bool(cloud.is_bigendian))
    count = int(cloud.width) * int(cloud.height)
    raw = _data_bytes(cloud.data)
    if raw.size < count * dtype.itemsize:
        raise ValueError(f'PointCloud2 data holds {raw.size} bytes, {count} points of {dtype.itemsize} need more')
    points = np.frombuffer(raw, dtype=dtype, count=count)
    if field_names is not None:
        missing = [name for name in field_names if name not in dtype.names]
        if missing:
            raise ValueError(f'PointCloud2 has no field {missing[0]!r} (fields: {", ".join(dtype.names)})')
        points = points[list(field_names)]
    if skip_nans and not cloud.is_dense:
        keep = np.ones(len(points), dtype=bool)
        for name in points.dtype.names:
            if points.dtype[name].kind == 'f':
                keep &= ~np.isnan(points[name])
        points = points[keep]
    if uvs is not None:
        index = np.asarray(uvs if isinstance(uvs, np.ndarray) else list(uvs), dtype=np.int64)
        if index.ndim == 2:  # (u, v) pairs: column u of row v
            index = index[:, 1] * int(cloud.width) + index[:, 0]
        points = points[index]
    if reshape_organized_cloud and cloud.height > 1:
        points = points.reshape(int(cloud.width), int(cloud.height))
    return points


def read_points_numpy(cloud: Any, field_names: Sequence[str] | None = None, skip_nans: bool = False,
                      uvs: Iterable | None = None, reshape_organized_cloud: bool = False) -> np.ndarray:
    """The points as a plain (N, fields) array, for math on e.g. x, y, z together.

    Raises:
        ValueError: the fields read do not all have one datatype (use read_points then).
    """
    chosen = [f for f in cloud.fields if field_names is None or f.name in field_names]
    if len({f.datatype for f in chosen}) > 1:
        raise ValueError('read_points_numpy needs fields of one datatype; use read_points() otherwise')
    points = read_points(cloud, field_names, skip_nans, uvs, reshape_organized_cloud)
    columns = [points[name] for name in points.dtype.names]
    return np.stack(columns, axis=-1) if columns else np.empty(points.shape + (0,))


def read_points_list(cloud: Any, field_names: Sequence[str] | None = None, skip_nans: bool = False,
                     uvs: Iterable | None = None) -> list[NamedTuple]:
    """The points as a list of namedtuples `Point(x=..., y=..., ...)` (slow: one object each)."""
    points = read_points(cloud, field_names, skip_nans, uvs)
    Point = namedtuple('Point', points.dtype.names)
    return [Point._make(record) for record in points.tolist()]


def create_cloud(header: Any, fields: Sequence[Any], points: Any, point_step: int | None = None) -> Any:
    """A PointCloud2 of `points` laid out by `fields`.

    Args:
        points: a structured array of dtype_from_fields(fields); an (N, fields) array when all
            fields share one datatype; an (W, H, ...) array for an organized cloud; or any
            iterable of per-point sequences.

    Raises:
        ValueError: the points do not match the fields.
    """
    dtype = dtype_from_fields(fields, point_step)
    if isinstance(points, np.ndarray) and points.dtype.names is not None:
        if points.dtype != dtype:
            raise ValueError('the structured array does not match the PointFields (names, order and types)')
        records = points
    else:
        array = np.asarray(points) if isinstance(points, np.ndarray) else np.asarray(list(map(tuple, points)))
        if array.size == 0:
            array = array.reshape(0, len(dtype.names))
        if array.shape[-1] != len(dtype.names):
            raise ValueError(f'each point needs {len(dtype.names)} values ({", ".join(dtype.names)}), '
                             f'got {array.shape[-1]}')
        records = np.zeros(array.shape[:-1], dtype=dtype)
        for column, name in enumerate(dtype.names):
            records[name] = array[..., column]
    if records.ndim > 2:
        raise ValueError('an organized cloud has at most two dimensions of points')
    width = records.shape[0] if records.ndim else 1
    height = records.shape[1] if records.ndim == 2 else 1
    cloud = PointCloud2(header=header, height=height, width=width, is_dense=False, is_bigendian=False,
                        fields=list(fields), point_step=dtype.itemsize, row_step=dtype.itemsize * width)
    cloud.data = np.ascontiguousarray(records).view(np.uint8).reshape(-1) if records.size else b''
    return cloud


def create_cloud_xyz32(header: Any, points: Any) -> Any:
    """A PointCloud2 with float32 x, y, z fields from (N, 3) points."""
    fields = [PointField(name=name, offset=4 * i, datatype=PointField.FLOAT32, count=1)
              for i, name in enumerate('xyz')]
    return create_cloud(header, fields, points)
