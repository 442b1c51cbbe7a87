"""rqt's tools as pages of the view: Plot (rqt_plot), Services (the service caller) and
Parameters (rqt_reconfigure). The topic monitor, graph and console are in pages.py.

Each page does its work in Python (subscriptions, calls, decimation) and sends the browser
only widgets and a few hundred numbers: a topic plotted at 50 Hz costs the page a redraw twice
a second, never a message per sample. Calls go out as futures completed by the view node's
executor, so a slow service never freezes the page.
"""
from __future__ import annotations

import html
import threading
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from zros.view.scene.fields import FieldError, check_field, field_value, fill_request, form_fields, \
    message_tree_html, split_plot_path
from zros.view.scene.pages import Page, boxed, release
from zros.view.scene.plot import PlotBuffer

if TYPE_CHECKING:
    from zros.view.scene.app import SceneView

__all__ = ['PlotPage', 'ServicesPage', 'ParametersPage', 'CALL_TIMEOUT']

CALL_TIMEOUT = 10.0      # [s] a service or parameter call not answered by then is reported
_COLORS = ('#2563eb', '#dc2626', '#16a34a', '#d97706', '#7c3aed', '#0891b2', '#db2777', '#4b5563')
_PARAMETER_SERVICES = ('describe_parameters', 'get_parameters', 'get_parameter_types', 'list_parameters',
                       'set_parameters', 'set_parameters_atomically', 'get_type_description')


def _note(level: str, text: str, **data: str) -> str:
    color = {'ok': '#16a34a', 'error': '#dc2626', 'warn': '#d97706'}.get(level, '#555')
    attrs = ''.join(f' data-{k}="{html.escape(v)}"' for k, v in data.items())
    return boxed(f'<div style="font-size:12px;color:{color}"{attrs}>{html.escape(text)}</div>')


class _Series:
    """One plotted field: where it comes from and what is wrong with it, if anything."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.topic = ''
        self.parts: list[str | int] = []
        self.error = ''


class PlotPage(Page):
    """rqt_plot: numeric fields by path (`/turtle1/pose/x`, `/odom/twist/twist/linear/x`,
    `/scan/ranges[0]`) as live time series, with pause, drag-to-zoom and CSV export."""

    title, icon = 'Plot', 'chart-line'
    POINTS = 500            # samples per series sent to the browser at most

    def __init__(self, paths: list[str] | tuple[str, ...] = ()) -> None:
        self.view: 'SceneView | None' = None
        self.buffer = PlotBuffer()
        self.series: dict[str, _Series] = {}
        self._subscriptions: dict[str, Any] = {}
        self._t0 = time.monotonic()
        self._lock = threading.Lock()
        self._chart_key: tuple[str, ...] | None = None
        self.chart: Any = None
        for path in paths:
            self.series[_plot_path(path)] = _Series(_plot_path(path))

    def build(self, view: 'SceneView') -> None:
        gui = view.gui
        self.view = view
        self.path_input = gui.add_text('Field', '/turtle1/pose/x', hint='topic/field[/index], e.g. /odom/twist/twist/'
                                       'linear/x or /scan/ranges[0]; several separated by commas')
        add = gui.add_button('Add', icon='plus')
        add.on_click(lambda _: [self.add(p) for p in self.path_input.value.split(',') if p.strip()])
        self.pause = gui.add_checkbox('Pause', False, hint='Freeze the picture (samples are still recorded); '
                                      'drag across the plot to zoom, double-click to zoom out')
        self.span = gui.add_number('Window [s]', 20.0, min=1.0, max=300.0, step=1.0)
        self.status = gui.add_html('')
        self._chart_order = self.status.order + 0.1
        with gui.add_folder('Series', expand_by_default=True):
            self.remove_choice = gui.add_dropdown('Remove', ['(none)'])
            remove = gui.add_button('Remove series', color='gray')
            remove.on_click(lambda _: self.remove(self.remove_choice.value))
            clear = gui.add_button('Clear samples', color='gray')
            clear.on_click(lambda _: self.buffer.clear())
            export = gui.add_button('Export CSV', icon='download')
            export.on_click(self._export)

    def add(self, path: str) -> None:
        """Plot one more field (subscribing when its topic is in the graph)."""
        path = _plot_path(path)
        with self._lock:
            if path not in self.series:
                self.series[path] = _Series(path)

    def remove(self, path: str) -> None:
        with self._lock:
            self.series.pop(path, None)
            topics = {s.topic for s in self.series.values()}
        self.buffer.remove(path)
        for topic in [t for t in self._subscriptions if t not in topics]:
            self._unsubscribe(topic)

    def _resolve(self) -> None:
        """Match series to topics of the graph, check their fields, subscribe."""
        from zros.typesupport import get_message
        view = self.view
        assert view is not None
        types = dict(view.topic_types())
        with self._lock:
            pending = [s for s in self.series.values() if not s.topic or s.error]
        for series in pending:
            try:
                topic, parts = split_plot_path(series.path, list(types))
                msg_type = get_message(types[topic][0])
                check_field(msg_type, parts)
            except FieldError as exc:
                series.error = str(exc) if str(exc).startswith(series.path) else f'{series.path}: {exc}'
                continue
            except Exception as exc:  # noqa: BLE001 - a type this machine does not have
                series.error = f'{series.path}: {exc}'
                continue
            series.topic, series.parts, series.error = topic, parts, ''
            if topic not in self._subscriptions:
                self._subscriptions[topic] = view.node.create_subscription(msg_type, topic, self._receiver(topic), 10)

    def _receiver(self, topic: str) -> Any:
        def received(msg: Any) -> None:        # one argument: a second one would ask for MessageInfo
            t = time.monotonic() - self._t0
            with self._lock:
                series = [s for s in self.series.values() if s.topic == topic and not s.error]
            for one in series:
                try:
                    self.buffer.add(one.path, t, field_value(msg, one.parts))
                except FieldError as exc:
                    one.error = f'{one.path}: {exc}'
        return received

    def _unsubscribe(self, topic: str) -> None:
        subscription = self._subscriptions.pop(topic, None)
        if self.view is not None:
            release(self.view.node.destroy_subscription, [subscription])

    def refresh(self, now: float) -> None:
        if self.view is None:
            return
        self._resolve()
        with self._lock:
            series = list(self.series.values())
        names = [s.path for s in series if not s.error]
        options = [s.path for s in series] or ['(none)']
        if tuple(options) != tuple(self.remove_choice.options):
            self.remove_choice.options = options
        lines = []
        for s in series:
            if s.error:
                lines.append(_note('error', s.error, series=s.path))
            else:
                last = self.buffer.last(s.path)
                lines.append(_note('ok' if last is not None else 'warn',
                                   f'{s.path}: {last:.4g}' if last is not None else f'{s.path}: no message yet',
                                   series=s.path))
        self.status.content = ''.join(lines) or _note('', 'Type a field path and press Add.')
        if self.pause.value:
            return
        end = time.monotonic() - self._t0
        data = self.buffer.window(names, end - float(self.span.value), end, self.POINTS)
        self._draw(tuple(names), data)

    def _draw(self, names: tuple[str, ...], data: tuple[np.ndarray, ...]) -> None:
        view = self.view
        assert view is not None
        if not names:
            data = (np.zeros(0), np.zeros(0))
        if self.chart is not None and names == self._chart_key:
            self.chart.data = data
            return
        if self.chart is not None:
            self.chart.remove()
        series = [{'label': 't [s]'}] + [{'label': name, 'stroke': _COLORS[i % len(_COLORS)], 'width': 2}
                                         for i, name in enumerate(names)] if names else [{'label': 't [s]'}, {'label': ''}]
        with self.tab:
            self.chart = view.gui.add_uplot(data, tuple(series), aspect=1.3, order=self._chart_order, padding=(12, 24, 0, 0),
                                            cursor={'drag': {'x': True, 'y': False}}, scales={'x': {'time': False}})
        self._chart_key = names

    def _export(self, event: Any) -> None:
        with self._lock:
            names = [s.path for s in self.series.values() if not s.error]
        content = self.buffer.to_csv(names).encode()
        if event.client is not None:
            event.client.send_file_download('plot.csv', content, save_immediately=True)

    def close(self) -> None:
        for topic in list(self._subscriptions):
            self._unsubscribe(topic)


class ServicesPage(Page):
    """The service caller: pick a service, fill its request in a form generated from its
    definition (defaults shown, types checked before sending), see the response or the error."""

    title, icon = 'Services', 'arrows-exchange'
    NONE = '(pick a service)'

    def __init__(self) -> None:
        self.view: 'SceneView | None' = None
        self.form: Any = None
        self.inputs: dict[str, Any] = {}
        self._service: tuple[str, str] | None = None
        self._clients: dict[tuple[str, str], Any] = {}
        self._pending: tuple[Any, float, str] | None = None

    def build(self, view: 'SceneView') -> None:
        gui = view.gui
        self.view = view
        self.choice = gui.add_dropdown('Service', [self.NONE], initial_value=self.NONE)
        self.choice.on_update(lambda _: self._pick(self.choice.value))
        self.show_parameter_services = gui.add_checkbox('Parameter services too', False)
        self.response = gui.add_html('')
        self._form_order = self.response.order - 0.1

    def _services(self) -> list[tuple[str, str]]:
        from zros.graph_content import is_hidden
        from zros.graph import EntityKind
        assert self.view is not None
        everything = bool(self.show_parameter_services.value)
        found = {(e.name, e.type) for e in self.view.graph_entities() if e.kind == EntityKind.SERVICE
                 and not is_hidden(e.name) and (everything or e.name.rsplit('/', 1)[-1] not in _PARAMETER_SERVICES)}
        return sorted(found)

    def refresh(self, now: float) -> None:
        if self.view is None:
            return
        options = [self.NONE] + [f'{name} · {srv_type}' for name, srv_type in self._services()]
        if self.choice.value not in options:
            options.append(self.choice.value)
        if tuple(options) != tuple(self.choice.options):
            self.choice.options = options
        if self._pending is not None:
            future, started, name = self._pending
            if not future.done() and now - started > CALL_TIMEOUT:
                future.cancel()
                self._pending = None
                self.response.content = _note('error', f'{name}: no response within {CALL_TIMEOUT:g} s',
                                              call='error')

    def _pick(self, choice: str) -> None:
        from zros.typesupport import get_service
        assert self.view is not None
        gui = self.view.gui
        if self.form is not None:
            self.form.remove()
            self.form, self.inputs = None, {}
        self.response.content = ''
        if ' · ' not in choice:
            self._service = None
            return
        name, srv_type = choice.split(' · ', 1)
        try:
            request_type = get_service(srv_type).Request
        except Exception as exc:  # noqa: BLE001 - a service type this machine does not have
            self.response.content = _note('error', f'cannot load {srv_type}: {exc}', call='error')
            return
        self._service = (name, srv_type)
        with self.tab:
            self.form = gui.add_folder(f'Request · {srv_type}', order=self._form_order)
        with self.form:
            fields = form_fields(request_type)
            if not fields:
                gui.add_html(_note('', 'This request has no fields.'))
            for field in fields:
                label, hint = field.path, f'{field.type_text} (default {field.default!r})'
                if field.kind == 'bool':
                    widget = gui.add_checkbox(label, field.default, hint=hint)
                elif field.kind == 'int':
                    widget = gui.add_number(label, field.default, step=1, hint=hint)
                elif field.kind == 'float':
                    widget = gui.add_number(label, field.default, step=0.01, hint=hint)
                else:
                    widget = gui.add_text(label, str(field.default), hint=hint)
                self.inputs[field.path] = widget
            call = gui.add_button('Call', icon='send')
            call.on_click(lambda _: self.call())

    def call(self) -> None:
        """Send the form's request; the response (or the error) shows under the form."""
        from zros.typesupport import get_service
        assert self.view is not None
        if self._service is None:
            return
        name, srv_type = self._service
        srv_class = get_service(srv_type)
        try:
            request = fill_request(srv_class.Request, {path: w.value for path, w in self.inputs.items()})
        except FieldError as exc:
            self.response.content = _note('error', f'not sent: {exc}', call='error')
            return
        client = self._clients.get(self._service)
        if client is None:
            client = self._clients[self._service] = self.view.node.create_client(srv_class, name)
        if not client.wait_for_service(timeout_sec=2.0):
            self.response.content = _note('error', f'{name}: no server for this service now', call='error')
            return
        started = time.monotonic()
        future = client.call_async(request)
        self._pending = (future, started, name)
        self.response.content = _note('', f'calling {name}…')
        future.add_done_callback(lambda f: self._answered(f, name, started))

    def _answered(self, future: Any, name: str, started: float) -> None:
        from zros.convert import message_to_ordereddict
        if self._pending is not None and self._pending[0] is future:
            self._pending = None
        if future.cancelled():
            return
        exc = future.exception()
        took = (time.monotonic() - started) * 1000
        if exc is not None:
            self.response.content = _note('error', f'{name} failed after {took:.0f} ms: {exc}', call='error')
            return
        tree = message_tree_html(message_to_ordereddict(future.result(), truncate_length=64))
        self.response.content = (_note('ok', f'Response from {name} in {took:.0f} ms', call='ok')
                                 + boxed(f'<div style="font-size:12px;font-family:monospace">{tree}</div>'))

    def close(self) -> None:
        if self.view is not None:
            release(self.view.node.destroy_client, self._clients.values())
        self._clients.clear()


class ParametersPage(Page):
    """rqt_reconfigure: a node's parameters with their descriptors (ranges as sliders, read-only
    shown as such); a change goes through set_parameters, and a refusal shows the node's reason.
    Changes made elsewhere (`zros param set`) arrive through /parameter_events."""

    title, icon = 'Parameters', 'adjustments'
    NONE = '(pick a node)'

    def __init__(self, node: str = '') -> None:
        self.view: 'SceneView | None' = None
        self.box: Any = None
        self.initial = node
        self.widgets: dict[str, Any] = {}
        self.types: dict[str, int] = {}
        self._client: Any = None
        self._node = ''
        self._events: Any = None

    def build(self, view: 'SceneView') -> None:
        from interfaces.rcl_interfaces.msg import ParameterEvent
        gui = view.gui
        self.view = view
        self.choice = gui.add_dropdown('Node', [self.NONE], initial_value=self.NONE)
        self.choice.on_update(lambda _: self.load(self.choice.value))
        reload = gui.add_button('Reload', icon='refresh', color='gray')
        reload.on_click(lambda _: self.load(self.choice.value))
        self.note = gui.add_html('')
        self._box_order = self.note.order + 0.1
        self._events = view.node.create_subscription(ParameterEvent, '/parameter_events', self._on_event, 100)

    def refresh(self, now: float) -> None:
        from zros.graph import EntityKind
        if self.view is None:
            return
        nodes = sorted({e.node_fqn for e in self.view.graph_entities() if e.kind == EntityKind.NODE
                        and not e.node_name.startswith('_')})
        options = [self.NONE] + nodes
        if self.choice.value not in options:
            options.append(self.choice.value)
        if tuple(options) != tuple(self.choice.options):
            self.choice.options = options
        if self.initial and self.initial in nodes:
            self.choice.value, self.initial = self.initial, ''

    def load(self, node: str) -> None:
        """Read `node`'s parameters and descriptors and build their widgets."""
        from zros.parameter_client import AsyncParameterClient
        assert self.view is not None
        if self._client is not None:
            self._client.destroy()
            self._client = None
        self._clear()
        self._node = node if node != self.NONE else ''
        if not self._node:
            self.note.content = ''
            return
        self._client = client = AsyncParameterClient(self.view.node, self._node)
        if not client.wait_for_services(2.0):
            self.note.content = _note('error', f'{node} has no parameter services', params='error')
            return
        self.note.content = _note('', f'reading the parameters of {node}…')
        client.list_parameters([], 0, callback=lambda f: self._listed(client, f))

    def _listed(self, client: Any, future: Any) -> None:
        if client is not self._client:
            return
        if future.exception() is not None:
            self.note.content = _note('error', f'{self._node}: {future.exception()}', params='error')
            return
        names = sorted(future.result().result.names)
        described = client.describe_parameters(names)
        values = client.get_parameters(names)
        done = threading.Event()

        def both(_future: Any) -> None:
            if described.done() and values.done() and not done.is_set():
                done.set()
                self._show(client, names, described, values)
        described.add_done_callback(both)
        values.add_done_callback(both)

    def _show(self, client: Any, names: list[str], described: Any, values: Any) -> None:
        from zros.parameter import parameter_value_to_python
        if client is not self._client:
            return
        if described.exception() is not None or values.exception() is not None:
            self.note.content = _note('error', f'{self._node}: {described.exception() or values.exception()}',
                                      params='error')
            return
        assert self.view is not None
        gui = self.view.gui
        with self.tab:
            self.box = gui.add_folder(f'{self._node} · {len(names)} parameters', order=self._box_order)
        with self.box:
            for name, descriptor, value in zip(names, described.result().descriptors, values.result().values):
                self.types[name] = int(value.type)
                self.widgets[name] = self._widget(gui, name, descriptor, parameter_value_to_python(value))
        self.note.content = _note('ok', f'{len(names)} parameters of {self._node}', params='ok')

    def _widget(self, gui: Any, name: str, descriptor: Any, value: Any) -> Any:
        import yaml
        hint = ' '.join(filter(None, [descriptor.description, descriptor.additional_constraints])) or None
        disabled = bool(descriptor.read_only)
        label = name + (' (read-only)' if disabled else '')
        ranges = list(descriptor.floating_point_range) or list(descriptor.integer_range)
        if isinstance(value, bool):
            widget = gui.add_checkbox(label, value, disabled=disabled, hint=hint)
        elif isinstance(value, (int, float)) and ranges:
            low, high, step = ranges[0].from_value, ranges[0].to_value, ranges[0].step
            if isinstance(value, int):
                step = int(step) or 1
            else:
                step = float(step) or (float(high) - float(low)) / 100.0 or 0.01
            widget = gui.add_slider(label, low, high, step, min(max(value, low), high), disabled=disabled, hint=hint)
        elif isinstance(value, (int, float)):
            widget = gui.add_number(label, value, step=1 if isinstance(value, int) else 0.01, disabled=disabled,
                                    hint=hint)
        elif isinstance(value, str):
            widget = gui.add_text(label, value, disabled=disabled, hint=hint)
        else:
            widget = gui.add_text(label, yaml.safe_dump(value, default_flow_style=True).strip() if value is not None
                                  else '', disabled=disabled, hint=hint)
        widget.on_update(lambda event: self._changed(event, name, widget))
        return widget

    def _changed(self, event: Any, name: str, widget: Any) -> None:
        """A user's change (not the page's own update of a value) -> set_parameters."""
        import yaml

        from zros.parameter import Parameter
        if event.client is None or self._client is None:
            return
        value = widget.value
        kind = Parameter.Type(self.types.get(name, 0))
        if kind in (Parameter.Type.BYTE_ARRAY, Parameter.Type.BOOL_ARRAY, Parameter.Type.INTEGER_ARRAY,
                    Parameter.Type.DOUBLE_ARRAY, Parameter.Type.STRING_ARRAY):
            try:
                value = yaml.safe_load(value)
            except yaml.YAMLError:
                self.note.content = _note('error', f'{name}: not a YAML list: {value!r:.60}', params='error')
                return
        elif kind == Parameter.Type.INTEGER:
            value = int(round(value))
        elif kind == Parameter.Type.DOUBLE:
            value = float(value)
        try:
            parameter = Parameter(name, value=value)
        except (TypeError, ValueError) as exc:
            self.note.content = _note('error', f'{name}: {exc}', params='error')
            return
        node = self._node
        self._client.set_parameters([parameter], callback=lambda f: self._set(f, node, name, value))

    def _set(self, future: Any, node: str, name: str, value: Any) -> None:
        if future.exception() is not None:
            self.note.content = _note('error', f'{node}: set {name} failed: {future.exception()}', params='error')
            return
        result = future.result().results[0]
        if result.successful:
            self.note.content = _note('ok', f'{node}: {name} = {value!r}', params='ok')
        else:
            self.note.content = _note('error', f'{node} refused {name} = {value!r}: {result.reason or "no reason given"}',
                                      params='refused')
            if self._client is not None:      # show the value the node kept
                self._client.get_parameters([name], callback=lambda f: self._restore(f, name))

    def _restore(self, future: Any, name: str) -> None:
        from zros.parameter import parameter_value_to_python
        if future.exception() is None and future.result().values:
            self._show_value(name, parameter_value_to_python(future.result().values[0]))

    def _show_value(self, name: str, value: Any) -> None:
        import yaml
        widget = self.widgets.get(name)
        if widget is None or value is None:
            return
        if isinstance(value, list):
            value = yaml.safe_dump(value, default_flow_style=True).strip()
        try:
            widget.value = value
        except (TypeError, ValueError):
            pass

    def _on_event(self, event: Any) -> None:
        from zros.parameter import parameter_value_to_python
        if not self._node or event.node != self._node:
            return
        for parameter in list(event.changed_parameters) + list(event.new_parameters):
            self._show_value(parameter.name, parameter_value_to_python(parameter.value))

    def _clear(self) -> None:
        if self.box is not None:
            self.box.remove()
        self.box, self.widgets, self.types = None, {}, {}

    def close(self) -> None:
        if self._client is not None:
            self._client.destroy()
            self._client = None
        if self.view is not None:
            release(self.view.node.destroy_subscription, [self._events])


def _plot_path(path: str) -> str:
    return '/' + path.strip().lstrip('/')
