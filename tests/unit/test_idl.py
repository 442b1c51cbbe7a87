"""Tests for zros.idl: the ROS 2 .msg/.srv/.action parser."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from zros.errors import InterfaceParseError
from zros.idl import (
    PRIMITIVE_TYPES,
    ActionSpec,
    Constant,
    Field,
    FieldType,
    MessageSpec,
    ServiceSpec,
    parse_action,
    parse_file,
    parse_message,
    parse_service,
)

SOURCE = '/x/Foo.msg'
INTERFACES = Path(__file__).parents[2] / 'interfaces'


def msg(text: str, package: str = 'pkg') -> MessageSpec:
    return parse_message(text, package, 'Foo', source=SOURCE)


def field(text: str) -> Field:
    spec = msg(text)
    assert len(spec.fields) == 1, spec.fields
    return spec.fields[0]


def constant(text: str) -> Constant:
    spec = msg(text)
    assert len(spec.constants) == 1, spec.constants
    return spec.constants[0]


def parse_error(func, *args, **kwargs) -> str:
    with pytest.raises(InterfaceParseError) as info:
        func(*args, **kwargs)
    message = str(info.value)
    assert '\n' not in message
    return message


def assert_error(text: str, line: int, *fragments: str) -> None:
    message = parse_error(msg, text)
    assert message.startswith(f'{SOURCE}:{line}: '), message
    for fragment in fragments:
        assert fragment in message, message


# --- types ---------------------------------------------------------------------------------------

@pytest.mark.parametrize('name', sorted(PRIMITIVE_TYPES))
def test_every_primitive(name):
    f = field(f'{name} value')
    assert f.name == 'value'
    assert f.type == FieldType(name)
    assert f.type.is_primitive and not f.type.is_array
    assert not f.has_default and f.default is None


def test_bounded_strings():
    spec = msg('string<=10 a\nwstring<=5 b\n')
    assert spec.fields[0].type == FieldType('string', string_bound=10)
    assert spec.fields[1].type == FieldType('wstring', string_bound=5)
    assert str(spec.fields[0].type) == 'string<=10'


@pytest.mark.parametrize('type_text, expected', [
    ('int32[3]', FieldType('int32', array='fixed', array_size=3)),
    ('int32[<=5]', FieldType('int32', array='bounded', array_size=5)),
    ('int32[]', FieldType('int32', array='unbounded')),
    ('string<=5[3]', FieldType('string', 5, 'fixed', 3)),
    ('string<=5[<=2]', FieldType('string', 5, 'bounded', 2)),
    ('wstring[]', FieldType('wstring', array='unbounded')),
    ('Point[2]', FieldType('pkg/msg/Point', array='fixed', array_size=2)),
    ('geometry_msgs/Point[<=4]', FieldType('geometry_msgs/msg/Point', None, 'bounded', 4)),
    ('geometry_msgs/msg/Point[]', FieldType('geometry_msgs/msg/Point', array='unbounded')),
])
def test_array_forms(type_text, expected):
    f = field(f'{type_text} items')
    assert f.type == expected
    assert f.type.is_array
    assert str(f.type) == type_text.replace('/msg/', '/').replace('Point[2]', 'pkg/Point[2]')


@pytest.mark.parametrize('type_text, base', [
    ('Point', 'pkg/msg/Point'),
    ('geometry_msgs/Point', 'geometry_msgs/msg/Point'),
    ('geometry_msgs/msg/Point', 'geometry_msgs/msg/Point'),
    ('Header', 'std_msgs/msg/Header'),
    ('std_msgs/Header', 'std_msgs/msg/Header'),
    ('time', 'builtin_interfaces/msg/Time'),
    ('duration', 'builtin_interfaces/msg/Duration'),
])
def test_nested_type_resolution(type_text, base):
    f = field(f'{type_text} member')
    assert f.type.base == base
    assert not f.type.is_primitive


def test_time_alias_arrays_and_dependencies():
    spec = msg('time[] stamps\nduration[2] spans\nHeader header\nint32 x\n')
    assert spec.fields[0].type == FieldType('builtin_interfaces/msg/Time', array='unbounded')
    assert spec.fields[1].type == FieldType('builtin_interfaces/msg/Duration', None, 'fixed', 2)
    assert spec.dependencies() == [
        'builtin_interfaces/msg/Time', 'builtin_interfaces/msg/Duration', 'std_msgs/msg/Header']


def test_message_spec_names():
    spec = parse_message('int32 x\n', 'my_pkg', 'Thing', source='/a/Thing.msg')
    assert spec.full_name == 'my_pkg/msg/Thing'
    assert spec.package == 'my_pkg' and spec.name == 'Thing'
    assert spec.source == '/a/Thing.msg'
    assert spec.text == 'int32 x\n'
    assert parse_message('', 'p', 'N', kind='srv').full_name == 'p/srv/N'


def test_tabs_and_multiple_spaces_separate_tokens():
    f = field('int32\t\tcount   \t 7   ')
    assert (f.name, f.default) == ('count', 7)


# --- comments ------------------------------------------------------------------------------------

def test_comments_everywhere():
    text = (
        '# file comment\n'
        '#\n'
        '\n'
        '   # indented comment\n'
        'int32 a  # trailing comment\n'
        'int32 b 3 # comment after default\n'
        'int32 c#no space\n'
        'int32 C=4 # comment after constant\n'
        '\t# tab-indented comment\n'
        '   \n'
    )
    spec = msg(text)
    assert [(f.name, f.default) for f in spec.fields] == [('a', None), ('b', 3), ('c', None)]
    assert spec.constants == (Constant('C', 'int32', 4),)


def test_hash_inside_quoted_values_is_not_a_comment():
    spec = msg(
        'string a "x # y"  # real comment\n'
        "string b 'x#y'\n"
        'string[] c ["p#q", \'r#s\', t]  # comment\n'
        'string D="1 # 2" # comment\n'
    )
    assert [f.default for f in spec.fields] == ['x # y', 'x#y', ['p#q', 'r#s', 't']]
    assert spec.constants[0].value == '1 # 2'


def test_hash_in_unquoted_string_starts_a_comment_like_rosidl():
    spec = msg('string a x#y\nstring B=foo # bar\n')
    assert spec.fields[0].default == 'x'
    assert spec.constants[0].value == 'foo'


# --- constants -----------------------------------------------------------------------------------

@pytest.mark.parametrize('line, expected', [
    ('bool FLAG=true', Constant('FLAG', 'bool', True)),
    ('bool FLAG=False', Constant('FLAG', 'bool', False)),
    ('bool FLAG=1', Constant('FLAG', 'bool', True)),
    ('byte B=255', Constant('B', 'byte', 255)),
    ('char C=65', Constant('C', 'char', 65)),
    ('int8 MIN=-128', Constant('MIN', 'int8', -128)),
    ('uint8 U=200', Constant('U', 'uint8', 200)),
    ('int16 I=-32768', Constant('I', 'int16', -32768)),
    ('uint16 U=65535', Constant('U', 'uint16', 65535)),
    ('int32 I=-5', Constant('I', 'int32', -5)),
    ('uint32 U=4294967295', Constant('U', 'uint32', 4294967295)),
    ('int64 I=-9223372036854775808', Constant('I', 'int64', -9223372036854775808)),
    ('uint64 U=18446744073709551615', Constant('U', 'uint64', 18446744073709551615)),
    ('uint8 HEX=0x1F', Constant('HEX', 'uint8', 31)),
    ('float32 F=1.5', Constant('F', 'float32', 1.5)),
    ('float64 F=-2e3', Constant('F', 'float64', -2000.0)),
    ('float64 F=3', Constant('F', 'float64', 3.0)),
    ('string S=hello world', Constant('S', 'string', 'hello world')),
    ('string S="  padded  "', Constant('S', 'string', '  padded  ')),
    ("string S='it''s'", None),  # unescaped inner quote: error, checked below
    ('string S=', Constant('S', 'string', '')),
    ('string S=""', Constant('S', 'string', '')),
    ('wstring W=wide', Constant('W', 'wstring', 'wide')),
    ('int32 SPACED = 7', Constant('SPACED', 'int32', 7)),
    ('int32 A_1=1', Constant('A_1', 'int32', 1)),
])
def test_constants(line, expected):
    if expected is None:
        assert_error(line, 1, 'unescaped')
        return
    c = constant(line)
    assert c == expected
    assert type(c.value) is type(expected.value)


def test_string_constant_quotes_and_escapes():
    spec = msg(
        'string A="say \\"hi\\""\n'
        "string B='it\\'s'\n"
        'string C=tab\\there\n'
        'string D=un"balanced\n'
        'string E=C:\\dir\n'
    )
    assert [c.value for c in spec.constants] == ['say "hi"', "it's", 'tab\there', 'un"balanced',
                                                 'C:\\dir']


def test_float_special_values():
    spec = msg('float64 A=inf\nfloat64 B=-inf\nfloat64 C=nan\nfloat32 D=3.4028235e38\n')
    a, b, c, d = (c.value for c in spec.constants)
    assert a == math.inf and b == -math.inf and math.isnan(c) and d == 3.4028235e38


# --- defaults ------------------------------------------------------------------------------------

@pytest.mark.parametrize('line, expected', [
    ('bool f true', True),
    ('bool f True', True),
    ('bool f false', False),
    ('bool f False', False),
    ('bool f 1', True),
    ('bool f 0', False),
    ('byte f 0', 0),
    ('byte f 255', 255),
    ('char f 97', 97),
    ('int8 f -128', -128),
    ('int8 f 127', 127),
    ('uint8 f 255', 255),
    ('int16 f -300', -300),
    ('uint16 f 0x10', 16),
    ('int32 f 42', 42),
    ('uint32 f 7', 7),
    ('int64 f -1', -1),
    ('uint64 f 1', 1),
    ('float32 f 1', 1.0),
    ('float32 f 1.5', 1.5),
    ('float64 f -2e3', -2000.0),
    ('float64 f 0.1', 0.1),
    ('string f hello', 'hello'),
    ('string f   hello world   ', 'hello world'),
    ('string f "with \\"quotes\\""', 'with "quotes"'),
    ("string f 'single'", 'single'),
    ('string f "line\\nbreak"', 'line\nbreak'),
    ('string f ""', ''),
    ('string<=5 f abcde', 'abcde'),
    ('string<=3 f "a\\nb"', 'a\nb'),
    ('wstring f "wide"', 'wide'),
    ('string f a=b', 'a=b'),
    ('string f "caf\\u00e9 €"', 'café €'),
])
def test_scalar_defaults(line, expected):
    f = field(line)
    assert f.has_default
    assert f.default == expected
    assert type(f.default) is type(expected)


@pytest.mark.parametrize('line, expected', [
    ('int32[] f [1, 2, 3]', [1, 2, 3]),
    ('int32[] f []', []),
    ('int32[] f [ ]', []),
    ('int32[3] f [1,2,3]', [1, 2, 3]),
    ('int32[<=5] f [1, 2]', [1, 2]),
    ('uint8[<=2] f []', []),
    ('bool[] f [true, False, 1, 0]', [True, False, True, False]),
    ('float64[2] f [1, -2.5e1]', [1.0, -25.0]),
    ('byte[2] f [0, 255]', [0, 255]),
    ('char[] f [65, 66]', [65, 66]),
    ('string[] f ["a", \'b\', c]', ['a', 'b', 'c']),
    ('string[] f ["a, b", \'c, d\']', ['a, b', 'c, d']),
    ('string[] f [" padded ", x y ]', [' padded ', 'x y']),
    ('string[] f ["say \\"hi\\""]', ['say "hi"']),
    ('string<=3[<=2] f [abc, "de"]', ['abc', 'de']),
    ('wstring[2] f [a, b]', ['a', 'b']),
])
def test_array_defaults(line, expected):
    f = field(line)
    assert f.has_default
    assert f.default == expected
    assert [type(v) for v in f.default] == [type(v) for v in expected]


def test_field_without_default():
    f = field('int32 x   # nothing here')
    assert f == Field('x', FieldType('int32'))


# --- services and actions ------------------------------------------------------------------------

SRV = """# request
int64 a
int64 b
---
# response
int64 sum
"""


def test_service_split():
    spec = parse_service(SRV, 'example_interfaces', 'AddTwoInts', source='/x/AddTwoInts.srv')
    assert isinstance(spec, ServiceSpec)
    assert spec.full_name == 'example_interfaces/srv/AddTwoInts'
    assert spec.request.full_name == 'example_interfaces/srv/AddTwoInts_Request'
    assert spec.response.full_name == 'example_interfaces/srv/AddTwoInts_Response'
    assert [f.name for f in spec.request.fields] == ['a', 'b']
    assert [f.name for f in spec.response.fields] == ['sum']
    assert spec.request.text == '# request\nint64 a\nint64 b\n'
    assert spec.response.text == '# response\nint64 sum\n'
    assert spec.text == SRV
    assert spec.source == spec.request.source == spec.response.source == '/x/AddTwoInts.srv'


def test_service_empty_parts_and_separator_with_comment():
    spec = parse_service('  ---   # nothing either way\n', 'std_srvs', 'Empty')
    assert spec.request.fields == () and spec.response.fields == ()
    spec = parse_service('---\nbool success\nstring message', 'std_srvs', 'Trigger')
    assert [f.name for f in spec.response.fields] == ['success', 'message']


def test_service_errors_report_file_lines():
    message = parse_error(parse_service, 'int32 a\n---\nint32 b\nflaot64 c\n', 'p', 'S',
                          source='/x/S.srv')
    assert message == "/x/S.srv:4: unknown primitive type 'flaot64'"
    message = parse_error(parse_service, 'int32 a\nint32 b\n', 'p', 'S', source='/x/S.srv')
    assert message.startswith('/x/S.srv:2: ') and "'---'" in message
    message = parse_error(parse_service, 'int32 a\n---\nint32 b\n---\nint32 c\n', 'p', 'S',
                          source='/x/S.srv')
    assert message.startswith('/x/S.srv:4: ') and 'unexpected' in message
    message = parse_error(parse_service, '---\nint32 x\nint32 x\n', 'p', 'S', source='/x/S.srv')
    assert message == "/x/S.srv:3: duplicate field name 'x' (first defined on line 2)"


ACTION = """int32 order
---
int32[] sequence
---
# feedback
int32[] partial_sequence
"""


def test_action_split():
    spec = parse_action(ACTION, 'action_tutorials', 'Fibonacci', source='/x/Fibonacci.action')
    assert isinstance(spec, ActionSpec)
    assert spec.full_name == 'action_tutorials/action/Fibonacci'
    assert spec.goal.full_name == 'action_tutorials/action/Fibonacci_Goal'
    assert spec.result.full_name == 'action_tutorials/action/Fibonacci_Result'
    assert spec.feedback.full_name == 'action_tutorials/action/Fibonacci_Feedback'
    assert [f.name for f in spec.goal.fields] == ['order']
    assert spec.result.fields[0].type == FieldType('int32', array='unbounded')
    assert spec.feedback.text == '# feedback\nint32[] partial_sequence\n'
    assert spec.text == ACTION


def test_action_errors_report_file_lines():
    message = parse_error(parse_action, 'int32 a\n---\nint32 b\n', 'p', 'A', source='/x/A.action')
    assert message.startswith('/x/A.action:3: ') and 'two' in message
    message = parse_error(parse_action, '---\n---\n---\n', 'p', 'A', source='/x/A.action')
    assert message.startswith('/x/A.action:3: ')
    message = parse_error(parse_action, 'int32 a\n---\nint32 b\n---\nint32 c\nint32 D=x\n',
                          'p', 'A', source='/x/A.action')
    assert message.startswith('/x/A.action:6: ') and "constant 'D'" in message


def test_separator_in_message_is_an_error():
    assert_error('int32 a\n---\nint32 b\n', 2, "'---'")


# --- malformed input -----------------------------------------------------------------------------

@pytest.mark.parametrize('text, line, fragments', [
    ('int32 x\nflaot64 y\n', 2, ["unknown primitive type 'flaot64'"]),
    ('int32\n', 1, ['missing name', "'int32'"]),
    ('int32 # just a comment\n', 1, ['missing name']),
    ('int32=5\n', 1, ['missing name']),
    ('int32 X\n', 1, ["invalid field name 'X'"]),
    ('int32 my__x\n', 1, ["invalid field name 'my__x'"]),
    ('int32 x_\n', 1, ["invalid field name 'x_'"]),
    ('int32 1x\n', 1, ["invalid field name '1x'"]),
    ('int32 x,\n', 1, ["invalid field name 'x,'"]),
    ('int32 x\nint32 x\n', 2, ["duplicate field name 'x'", 'line 1']),
    ('int32 A=1\n\nint32 A=2\n', 3, ["duplicate constant name 'A'"]),
    ('int32 lower=1\n', 1, ["invalid constant name 'lower'"]),
    ('int32 A__B=1\n', 1, ["invalid constant name 'A__B'"]),
    ('int32 B_=1\n', 1, ["invalid constant name 'B_'"]),
    ('int32[] A=[1]\n', 1, ["constant 'A'", "'int32[]'"]),
    ('string<=3 A=abc\n', 1, ["constant 'A'", "'string<=3'"]),
    ('time T=1\n', 1, ["constant 'T'", "'time'"]),
    ('Point P=1\n', 1, ["constant 'P'"]),
    ('int32 A=\n', 1, ["missing value for constant 'A'"]),
    ('int32 A=1.5\n', 1, ["constant 'A'", "'1.5' is not an integer"]),
    ('uint8 A=256\n', 1, ["'256' is out of range for uint8"]),
    ('int32[0] x\n', 1, ["array size in 'int32[0]'"]),
    ('int32[<=0] x\n', 1, ["'int32[<=0]'"]),
    ('int32[abc] x\n', 1, ["'int32[abc]'", "'abc'"]),
    ('int32[-1] x\n', 1, ["'int32[-1]'"]),
    ('int32] x\n', 1, ["invalid type 'int32]'"]),
    ('int32[3][2] x\n', 1, ["invalid type 'int32[3][2]'"]),
    ('string<=0 x\n', 1, ["string bound in 'string<=0'"]),
    ('string<=abc x\n', 1, ["'string<=abc'"]),
    ('int32<=5 x\n', 1, ["'int32<=5'", 'only string and wstring']),
    ('Bad_Name x\n', 1, ["invalid message name 'Bad_Name'"]),
    ('Bad_pkg/Point x\n', 1, ["invalid package name 'Bad_pkg'"]),
    ('pkg/point x\n', 1, ["invalid message name 'point'"]),
    ('a/b/C/D x\n', 1, ["invalid type 'a/b/C/D'"]),
    ('pkg/srv/Thing x\n', 1, ["invalid type 'pkg/srv/Thing'"]),
    ('  int32 x\n', 1, ['indentation']),
    ('@optional int32 x\n', 1, ["annotation '@optional'"]),
    ('int8 x 200\n', 1, ["field 'x'", "'200' is out of range for int8 (-128..127)"]),
    ('uint8 x -1\n', 1, ["'-1' is out of range for uint8"]),
    ('byte x 256\n', 1, ["'256' is out of range for byte (0..255)"]),
    ('char x a\n', 1, ["'a' is not an integer"]),
    ('int32 x 1 2\n', 1, ["'1 2' is not an integer"]),
    ('bool x yes\n', 1, ["'yes' is not a bool"]),
    ('float64 x 1.2.3\n', 1, ["'1.2.3' is not a floating point number"]),
    ('float32 x 1e39\n', 1, ["'1e39' is out of range for float32"]),
    ('string<=3 x abcd\n', 1, ['more than the bound 3']),
    ('string<=2 x "a\\"b"\n', 1, ['more than the bound 2']),
    ('string x "a"b"\n', 1, ['unescaped']),
    ('string x "abc\\"\n', 1, ['unterminated']),
    ('string x abc\\\n', 1, ['invalid escape sequence']),
    ('string x "\\x4"\n', 1, ['invalid escape sequence']),
    ('string x "\\N{NO SUCH NAME}"\n', 1, ['invalid escape sequence']),
    ('Point p 1\n', 1, ["field 'p'", 'primitive']),
    ('Point[] p [1]\n', 1, ["field 'p'", 'primitive']),
    ('int32[3] x [1, 2]\n', 1, ["'[1, 2]' has 2 element(s)", 'exactly 3']),
    ('int32[3] x [1, 2, 3, 4]\n', 1, ['exactly 3']),
    ('int32[<=2] x [1, 2, 3]\n', 1, ['more than the 2']),
    ('int32[] x 1, 2\n', 1, ["'1, 2' must be enclosed in '[' and ']'"]),
    ('int32[] x [1, 2\n', 1, ["must be enclosed in '[' and ']'"]),
    ('int32[] x [1,,2]\n', 1, ['empty element']),
    ('int32[] x [1, 2,]\n', 1, ['empty element']),
    ('int32[] x [1, a]\n', 1, ["element 1", "'a' is not an integer"]),
    ('uint8[] x [1, 300]\n', 1, ["element 1", "'300' is out of range for uint8"]),
    ('string<=2[] x [ab, abc]\n', 1, ['element 1', 'more than the bound 2']),
    ('string[] x ["a" b]\n', 1, ['unexpected text after "a"']),
    ('string[] x ["a, b]\n', 1, ['unterminated']),
    ('string[] x [a, , b]\n', 1, ['empty element']),
])
def test_malformed(text, line, fragments):
    assert_error(text, line, *fragments)


def test_error_message_is_exactly_source_line_reason():
    message = parse_error(msg, '# comment\n\nflaot64 x\n')
    assert message == "/x/Foo.msg:3: unknown primitive type 'flaot64'"


@pytest.mark.parametrize('package, name', [('Bad', 'Foo'), ('pkg', 'foo'), ('pkg', 'Foo_Bar')])
def test_invalid_interface_names(package, name):
    message = parse_error(parse_message, 'int32 x\n', package, name, source=SOURCE)
    assert message.startswith(f'{SOURCE}:1: invalid ')
    assert f"'{package if package == 'Bad' else name}'" in message


# --- files ---------------------------------------------------------------------------------------

def test_parse_file_infers_package_kind_and_name(tmp_path):
    base = tmp_path / 'my_pkg'
    for kind, text in [('msg', 'int32 x\n'), ('srv', SRV), ('action', ACTION)]:
        (base / kind).mkdir(parents=True)
        (base / kind / f'Thing.{kind}').write_text(text, encoding='utf-8')
    message = parse_file(base / 'msg' / 'Thing.msg')
    assert isinstance(message, MessageSpec) and message.full_name == 'my_pkg/msg/Thing'
    assert message.source == str(base / 'msg' / 'Thing.msg')
    service = parse_file(str(base / 'srv' / 'Thing.srv'))
    assert isinstance(service, ServiceSpec) and service.full_name == 'my_pkg/srv/Thing'
    action = parse_file(base / 'action' / 'Thing.action')
    assert isinstance(action, ActionSpec) and action.full_name == 'my_pkg/action/Thing'


def test_parse_file_errors(tmp_path):
    (tmp_path / 'pkg' / 'msg').mkdir(parents=True)
    missing = tmp_path / 'pkg' / 'msg' / 'Missing.msg'
    assert parse_error(parse_file, missing).startswith(f'{missing}:1: cannot read file')

    binary = tmp_path / 'pkg' / 'msg' / 'Binary.msg'
    binary.write_bytes(b'int32 x\nstring s \xff\n')
    assert parse_error(parse_file, binary).startswith(f'{binary}:2: not valid UTF-8')

    wrong_dir = tmp_path / 'pkg' / 'msg' / 'Wrong.srv'
    wrong_dir.write_text('---\n', encoding='utf-8')
    assert parse_error(parse_file, wrong_dir).startswith(f'{wrong_dir}:1: ')

    broken = tmp_path / 'pkg' / 'msg' / 'Broken.msg'
    broken.write_text('int32 x\nint32 x\n', encoding='utf-8')
    assert parse_error(parse_file, broken) == (
        f"{broken}:2: duplicate field name 'x' (first defined on line 1)")


def test_every_shipped_interface_parses():
    files = sorted(p for p in INTERFACES.rglob('*')
                   if p.suffix in ('.msg', '.srv', '.action') and p.is_file())
    if not files:
        pytest.skip(f'no interface files under {INTERFACES}')
    for path in files:
        spec = parse_file(path)
        package, kind = path.parent.parent.name, path.parent.name
        assert spec.full_name == f'{package}/{kind}/{path.stem}'
