"""Round trips checked on generated input (hypothesis): what one side writes, the other reads
back unchanged, for any value and not only the examples the other tests chose.

- the MessagePack codec (zros.message) over message types generated field by field (every
  primitive, bounded strings, fixed / bounded / unbounded arrays, nested messages);
- CDR (zros.bag.cdr) over the shipped message types (but wstring ones), filled with generated values;
- transforms (zros.tf_transformations): Euler angles <-> quaternion <-> matrix, for every axes
  convention, and composition with the inverse;
- map files (zros.map_io): save_map -> load_map of generated grids;
- saved pose graphs (zros.slam.serialization): FILE.posegraph + FILE.data of generated graphs;
- launch substitutions (zros.launch.template): describe() writes a template back as text that
  parse() reads as the same template, and literal text survives any characters.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from unit.test_launch_parse import Ctx
from zros import tf_transformations as tft
from zros import typesupport
from zros.bag.cdr import CdrCodec
from zros.bag.definition import message_definition
from zros.idl import FieldType, parse_message
from zros.launch.template import Call, describe, parse
from zros.map_io import OccupancyMap, load_map, save_map
from zros.message import deserialize, make_message_class, serialize
from zros.slam.pose_graph import Edge
from zros.slam.scan import ScanPoints
from zros.slam.serialization import SerializedGraph, read_pose_graph, write_pose_graph

#: Every property runs this many generated cases; no deadline (a shared CI machine is slow).
ROUND_TRIP = settings(max_examples=25, deadline=None,
                      suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


# -- values of any message type -----------------------------------------------------------------
_INTS = {'char': (0, 255), 'int8': (-2**7, 2**7 - 1), 'uint8': (0, 2**8 - 1), 'int16': (-2**15, 2**15 - 1),
         'uint16': (0, 2**16 - 1), 'int32': (-2**31, 2**31 - 1), 'uint32': (0, 2**32 - 1),
         'int64': (-2**63, 2**63 - 1), 'uint64': (0, 2**64 - 1)}


def scalars(ftype: FieldType, *, nan: bool = False) -> st.SearchStrategy[Any]:
    """One value of `ftype`'s element type, as a message field accepts it."""
    base = ftype.base
    if base == 'bool':
        return st.booleans()
    if base == 'byte':
        return st.binary(min_size=1, max_size=1)
    if base in _INTS:
        return st.integers(*_INTS[base])
    if base == 'float32':
        return st.floats(width=32, allow_nan=nan)
    if base == 'float64':
        return st.floats(allow_nan=nan)
    if base in ('string', 'wstring'):
        return st.text(max_size=12 if ftype.string_bound is None else ftype.string_bound)
    return messages(typesupport.get_message(base), nan=nan)


def field_values(ftype: FieldType, *, nan: bool = False) -> st.SearchStrategy[Any]:
    element = scalars(ftype, nan=nan)
    if ftype.array == 'fixed':
        return st.lists(element, min_size=ftype.array_size, max_size=ftype.array_size)
    if ftype.array == 'bounded':
        return st.lists(element, max_size=ftype.array_size)
    if ftype.array == 'unbounded':
        return st.lists(element, max_size=4)
    return element


@st.composite
def messages(draw: st.DrawFn, cls: type, *, nan: bool = False) -> Any:
    """A `cls` message with every field set to a generated value."""
    msg = cls()
    for field in cls._SPEC.fields:
        setattr(msg, field.name, draw(field_values(field.type, nan=nan)))
    return msg


# -- message types, generated field by field -------------------------------------------------------
_PRIMITIVES = ['bool', 'byte', 'char', 'int8', 'uint8', 'int16', 'uint16', 'int32', 'uint32', 'int64',
               'uint64', 'float32', 'float64', 'string', 'wstring', 'string<=3',
               'geometry_msgs/Point', 'std_msgs/Header', 'builtin_interfaces/Time']
_ARRAY_SUFFIXES = st.sampled_from(['', '', '[]', '[2]', '[<=3]'])


@st.composite
def message_types(draw: st.DrawFn) -> type:
    """A message class built from generated IDL text: 1 to 6 fields of any kind."""
    count = draw(st.integers(1, 6))
    lines = [f'{draw(st.sampled_from(_PRIMITIVES))}{draw(_ARRAY_SUFFIXES)} field{i}' for i in range(count)]
    spec = parse_message('\n'.join(lines) + '\n', 'hypothesis_msgs', 'Generated')
    return make_message_class(spec, typesupport.get_message)


@st.composite
def typed_messages(draw: st.DrawFn, *, nan: bool = False) -> tuple[type, Any]:
    cls = draw(message_types())
    return cls, draw(messages(cls, nan=nan))


@ROUND_TRIP
@given(typed_messages())
def test_codec_decodes_what_it_encodes(typed):
    cls, msg = typed
    data = serialize(msg)
    back = deserialize(data, cls)
    assert back == msg, cls._SPEC.text
    assert serialize(back) == data


@ROUND_TRIP
@given(typed_messages(nan=True))
def test_codec_bytes_survive_a_round_trip_even_with_nan(typed):
    """NaN != NaN, so the messages cannot be compared; the bytes can."""
    cls, msg = typed
    data = serialize(msg)
    assert serialize(deserialize(data, cls)) == data


# -- CDR, over the shipped message types --------------------------------------------------------------
#: Every shipped message type but those with a wstring, which CDR refuses (tests/unit/test_cdr.py).
_CDR_MESSAGES = sorted(name for name in typesupport.list_interfaces()
                       if '/msg/' in name and 'wstring' not in message_definition(name))


@pytest.fixture(scope='module')
def cdr() -> CdrCodec:
    return CdrCodec()


@ROUND_TRIP
@given(data=st.data(), name=st.sampled_from(_CDR_MESSAGES))
def test_cdr_decodes_what_it_encodes(cdr, data, name):
    cls = typesupport.get_message(name)
    msg = data.draw(messages(cls), label=name)
    assert cdr.deserialize(cdr.serialize(msg), cls) == msg


# -- transforms -------------------------------------------------------------------------------------
#: The 24 conventions: static or rotating frame, three axes with no axis twice in a row.
AXES = [frame + axes for frame in 'sr' for axes in ('xyz', 'xyx', 'xzy', 'xzx', 'yzx', 'yzy', 'yxz', 'yxy',
                                                    'zxy', 'zxz', 'zyx', 'zyz')]
angles = st.floats(-math.pi, math.pi)


@st.composite
def unit_quaternions(draw: st.DrawFn) -> np.ndarray:
    q = np.array(draw(st.lists(st.floats(-1, 1), min_size=4, max_size=4)))
    assume(np.linalg.norm(q) > 0.1)
    return q / np.linalg.norm(q)


@st.composite
def transforms(draw: st.DrawFn) -> np.ndarray:
    """A rigid transform: a rotation and a translation within 100 m."""
    matrix = tft.quaternion_matrix(draw(unit_quaternions()))
    matrix[:3, 3] = draw(st.lists(st.floats(-100, 100), min_size=3, max_size=3))
    return matrix


@ROUND_TRIP
@given(ai=angles, aj=angles, ak=angles, axes=st.sampled_from(AXES))
def test_euler_angles_read_back_from_their_matrix_give_the_same_rotation(ai, aj, ak, axes):
    """Angles are not unique (gimbal lock, wrap-around), the rotation they give is."""
    matrix = tft.euler_matrix(ai, aj, ak, axes)
    again = tft.euler_matrix(*tft.euler_from_matrix(matrix, axes), axes)
    np.testing.assert_allclose(again, matrix, atol=1e-9)


@ROUND_TRIP
@given(ai=angles, aj=angles, ak=angles, axes=st.sampled_from(AXES))
def test_euler_angles_through_a_quaternion_give_the_same_rotation(ai, aj, ak, axes):
    q = tft.quaternion_from_euler(ai, aj, ak, axes)
    assert np.linalg.norm(q) == pytest.approx(1.0)
    np.testing.assert_allclose(tft.quaternion_matrix(q), tft.euler_matrix(ai, aj, ak, axes), atol=1e-9)
    back = tft.quaternion_from_euler(*tft.euler_from_quaternion(q, axes), axes)
    assert abs(np.dot(back, q)) == pytest.approx(1.0)   # q and -q are one rotation


@ROUND_TRIP
@given(q=unit_quaternions())
def test_quaternion_to_matrix_and_back(q):
    back = tft.quaternion_from_matrix(tft.quaternion_matrix(q))
    assert abs(np.dot(back, q)) == pytest.approx(1.0)


@ROUND_TRIP
@given(q1=unit_quaternions(), q0=unit_quaternions())
def test_quaternion_product_is_the_matrix_product(q1, q0):
    np.testing.assert_allclose(tft.quaternion_matrix(tft.quaternion_multiply(q1, q0)),
                               tft.quaternion_matrix(q1) @ tft.quaternion_matrix(q0), atol=1e-9)
    identity = tft.quaternion_multiply(q1, tft.quaternion_inverse(q1))
    assert abs(identity[3]) == pytest.approx(1.0)


@ROUND_TRIP
@given(a=transforms(), b=transforms())
def test_a_transform_composed_with_its_inverse_is_the_identity(a, b):
    np.testing.assert_allclose(tft.concatenate_matrices(a, tft.inverse_matrix(a)), np.eye(4), atol=1e-9)
    np.testing.assert_allclose(tft.inverse_matrix(tft.concatenate_matrices(a, b)),
                               tft.concatenate_matrices(tft.inverse_matrix(b), tft.inverse_matrix(a)), atol=1e-9)


# -- map files ----------------------------------------------------------------------------------------
@st.composite
def grids(draw: st.DrawFn, values: list[int]) -> OccupancyMap:
    height, width = draw(st.integers(1, 12)), draw(st.integers(1, 12))
    cells = draw(st.lists(st.sampled_from(values), min_size=height * width, max_size=height * width))
    resolution = draw(st.floats(2.0**-10, 10.0, width=32))
    origin = tuple(draw(st.floats(-1000, 1000)) for _ in range(3))
    return OccupancyMap(np.array(cells, dtype=np.int8).reshape(height, width), resolution, origin)


@ROUND_TRIP
@given(grid=grids([-1, 0, 100]), image_format=st.sampled_from(['pgm', 'png']))
def test_a_trinary_map_loads_as_it_was_saved(tmp_path, grid, image_format):
    yaml_path, _ = save_map(grid, tmp_path / 'map', mode='trinary', image_format=image_format)
    loaded = load_map(yaml_path)
    assert loaded.data.tolist() == grid.data.tolist()
    assert np.float32(loaded.resolution) == np.float32(grid.resolution)
    assert loaded.origin == grid.origin


@ROUND_TRIP
@given(grid=grids(list(range(-1, 101))))
def test_a_raw_map_loads_as_it_was_saved(tmp_path, grid):
    yaml_path, _ = save_map(grid, tmp_path / 'map', mode='raw')
    assert load_map(yaml_path).data.tolist() == grid.data.tolist()


# -- saved pose graphs --------------------------------------------------------------------------------
@st.composite
def pose_graphs(draw: st.DrawFn) -> SerializedGraph:
    """Any graph serialize_map can write: N nodes (maybe none), scans of any size (maybe empty),
    edges between distinct nodes."""
    count = draw(st.integers(0, 5))
    number = st.floats(-1e6, 1e6)

    def array(*shape: int, dtype: Any = np.float64) -> np.ndarray:
        size = int(np.prod(shape))
        return np.array(draw(st.lists(number, min_size=size, max_size=size)), dtype=dtype).reshape(shape)
    scans = [ScanPoints(array(2), array(draw(st.integers(0, 4)), 2, dtype=np.float32),
                        array(draw(st.integers(0, 4)), 2, dtype=np.float32)) for _ in range(count)]
    edges = []
    if count >= 2:
        for _ in range(draw(st.integers(0, 4))):
            i, j = draw(st.lists(st.integers(0, count - 1), min_size=2, max_size=2, unique=True))
            edges.append(Edge(i, j, array(3), array(3, 3), draw(st.booleans())))
    parameters = {'resolution': draw(st.floats(0.01, 1.0)), 'do_loop_closing': draw(st.booleans())}
    return SerializedGraph(array(count, 3), array(count, 3), array(count), scans, edges, parameters)


@ROUND_TRIP
@given(graph=pose_graphs())
def test_a_pose_graph_reads_back_as_it_was_written(tmp_path, graph):
    written = write_pose_graph(tmp_path / 'graph', graph)
    assert [p.name for p in written] == ['graph.posegraph', 'graph.data']
    read = read_pose_graph(tmp_path / 'graph.posegraph')
    for name in ('poses', 'odom', 'travel'):
        assert np.array_equal(getattr(read, name), getattr(graph, name)), name
    assert len(read.scans) == len(graph.scans) and all(
        all(np.array_equal(a, b) for a, b in zip(r, g)) for r, g in zip(read.scans, graph.scans))
    assert [(e.i, e.j, e.robust) for e in read.edges] == [(e.i, e.j, e.robust) for e in graph.edges]
    assert all(np.array_equal(r.measurement, g.measurement) and np.array_equal(r.information, g.information)
               for r, g in zip(read.edges, graph.edges))
    assert read.parameters == graph.parameters


# -- launch substitutions -----------------------------------------------------------------------------
#: Literal text with every character the grammar gives a meaning to.
literals = st.text(st.sampled_from('ab $()\\\'"\t-_.:/'), min_size=1, max_size=8)


def _joined(parts: list) -> tuple:
    """A template as parse() gives it: adjacent literals merged, no empty ones."""
    out: list = []
    for part in parts:
        if isinstance(part, str) and out and isinstance(out[-1], str):
            out[-1] += part
        elif part != '':
            out.append(part)
    return tuple(out)


def templates(depth: int = 2) -> st.SearchStrategy[tuple]:
    """Literals and `$(var ...)`, `$(env ...)` calls whose arguments are templates in turn."""
    part = literals if depth == 0 else st.one_of(literals, calls(depth - 1))
    return st.lists(part, max_size=4).map(_joined)


def calls(depth: int) -> st.SearchStrategy[Call]:
    argument = templates(depth).filter(bool)
    return st.builds(Call, st.sampled_from(['var', 'env']),
                     st.lists(argument, min_size=1, max_size=2).map(tuple))


@ROUND_TRIP
@given(templates())
def test_a_template_written_back_as_text_parses_to_itself(template):
    assert parse(describe(template)) == template


@ROUND_TRIP
@given(literals, literals)
def test_literal_text_survives_describe_parse_and_perform(text, value):
    """Whatever the characters, a literal performs to itself, and `$(var x)` to x's value."""
    ctx = Ctx(x=value)
    assert ctx(describe((text,))) == text
    assert ctx(describe((text, Call('var', (('x',),)), text))) == text + value + text
