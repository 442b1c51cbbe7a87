"""rqt's tools as pages of the view, driven in a real headless Chromium against real nodes
(turtlesim, the parameter demo's param_talker): the plotted value moves when the turtle moves
and a wrong field says so, the CSV export downloads, the topic monitor shows the last message,
a service call from the form spawns a turtle, a slider change is what `zros param get` reads,
and a refused change shows the node's reason. (Console and graph: tests/integration/test_view_browser.py.)

One view for the module, opened on the Plot page as `zros run rqt_plot rqt_plot /turtle1/pose/x`
opens it.
"""
from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

import pytest

from conftest import background_node, wait_until
from zros.view.headless import Browser, find_chromium

pytestmark = pytest.mark.skipif(find_chromium() is None, reason='Debian chromium is not installed (.ci/run '
                                'installs it where apt-get is available)')

SHOTS = Path(os.environ['ZROS_VIEW_SHOTS']) if os.environ.get('ZROS_VIEW_SHOTS') else None   # to look at them


class Rqt:
    def __init__(self, view: Any, node: Any, browser: Browser, downloads: Path) -> None:
        self.view, self.node, self.browser, self.downloads = view, node, browser, downloads

    def page(self, title: str) -> Any:
        return next(p for p in self.view.pages if p.title == title)

    def text(self) -> str:
        return self.browser.evaluate('document.body.innerText')

    def shot(self, tmp_path: Path, name: str) -> None:
        self.browser.save_screenshot(SHOTS / name if SHOTS else tmp_path / name)


@pytest.fixture(scope='module')
def rqt(module_domain, module_spawn, tmp_path_factory):
    from zros.view.scene.app import SceneView
    module_spawn.node('turtlesim', 'turtlesim_node')
    module_spawn.node('demo_nodes', 'param_talker')
    downloads = tmp_path_factory.mktemp('downloads')
    with background_node('rqt_test') as node, \
            SceneView(node, port=0, tf=False, first_page='Plot', plot=['/turtle1/pose/x']) as view, \
            Browser(width=1500, height=900) as browser:
        browser.send('Page.setDownloadBehavior', behavior='allow', downloadPath=str(downloads))
        browser.open(view.url, wait_for='document.querySelector("[role=tab]")', timeout=60)
        browser.evaluate('document.querySelectorAll(".mantine-Notification-closeButton").forEach(b => b.click())')
        yield Rqt(view, node, browser, downloads)


def _call(node: Any, srv_type: Any, name: str, request: Any) -> Any:
    client = node.create_client(srv_type, name)
    try:
        assert client.wait_for_service(timeout_sec=20), f'{name} is not served'
        future = client.call_async(request)
        assert future.wait(20), f'{name} did not answer'
        return future.result()
    finally:
        node.destroy_client(client)


def test_plot_follows_the_turtle_and_exports_csv(rqt, tmp_path):
    from interfaces.turtlesim.srv import TeleportAbsolute
    browser = rqt.browser
    selected = browser.evaluate('[...document.querySelectorAll("[role=tab][aria-selected=true]")]'
                                '.map(t => t.innerText.trim())')
    assert 'Plot' in selected and 'Topics' not in selected, selected      # the page rqt_plot opens on
    browser.wait_for('document.body.innerText.includes("/turtle1/pose/x: 5.54")', timeout=30)
    _call(rqt.node, TeleportAbsolute, '/turtle1/teleport_absolute', TeleportAbsolute.Request(x=2.0, y=5.0))
    browser.wait_for('document.body.innerText.includes("/turtle1/pose/x: 2")', timeout=20)
    plot = rqt.page('Plot')
    wait_until(lambda: plot.chart is not None and plot.chart.data[1].size and plot.chart.data[1][-1] == 2.0, 20,
               message='the chart to end at x = 2')
    assert plot.chart.data[1].max() == pytest.approx(5.544, abs=0.01)     # where the turtle was
    assert browser.evaluate('document.querySelectorAll(".uplot canvas").length') >= 1
    # A field that does not exist says so.
    browser.fill('Field', '/turtle1/pose/q')
    wait_until(lambda: plot.path_input.value == '/turtle1/pose/q', 10, message='the typed path')
    browser.click_text('Add')
    browser.wait_for('document.body.innerText.includes("/turtle1/pose/q: turtlesim/msg/Pose has no field \'q\'")',
                     timeout=20)
    assert plot._chart_key == ('/turtle1/pose/x',)
    rqt.shot(tmp_path, 'rqt_plot.png')
    # CSV export: every sample, in the browser's download folder.
    browser.click_text('Export CSV')
    csv = wait_until(lambda: (rqt.downloads / 'plot.csv').exists() and (rqt.downloads / 'plot.csv').read_text(), 20,
                     message='plot.csv to be downloaded')
    rows = [line.split(',') for line in csv.splitlines()]
    assert rows[0] == ['time', '/turtle1/pose/x'] and len(rows) > 20      # the wrong field is not plotted
    assert float(rows[-1][1]) == 2.0


def test_topic_monitor_shows_rate_bandwidth_and_the_last_message(rqt, tmp_path):
    browser = rqt.browser
    browser.click_text('Topics')
    browser.choose('Message of', '/turtle1/pose')
    text = browser.wait_for('(() => { const t = document.querySelector("[data-message-tree=\'/turtle1/pose\']");'
                            ' return t && t.innerText.includes("theta") && t.innerText; })()', timeout=20)
    assert 'linear_velocity' in text
    row = browser.wait_for('[...document.querySelectorAll("tr")].map(r => r.innerText)'
                           '.find(t => t.includes("/turtle1/pose\\n") && t.includes("Hz") && t.includes("B/s"))')
    assert 'turtlesim/msg/Pose' in row
    rqt.shot(tmp_path, 'rqt_topics.png')


def test_service_caller_spawns_a_turtle(rqt, tmp_path):
    browser = rqt.browser
    browser.click_text('Services')
    browser.choose('Service', '/spawn · turtlesim/srv/Spawn')
    browser.fill('x', '3')
    browser.fill('y', '4')
    browser.fill('name', 'browser_turtle')
    page = rqt.page('Services')
    wait_until(lambda: page.inputs['name'].value == 'browser_turtle' and page.inputs['y'].value == 4, 10,
               message='the typed request')
    browser.click_text('Call')
    text = browser.wait_for('(() => { const n = document.querySelector("[data-call]"); return n && n.innerText; })()',
                            timeout=20)
    assert 'Response from /spawn' in text, text
    wait_until(lambda: '/browser_turtle/pose' in dict(rqt.node.get_topic_names_and_types()), 20,
               message='the spawned turtle in the graph')
    browser.wait_for('document.body.innerText.includes("browser_turtle")')
    rqt.shot(tmp_path, 'rqt_services.png')


def test_parameters_slider_and_refusal(rqt, tmp_path, zros_cli):
    browser = rqt.browser
    browser.click_text('Parameters')
    browser.choose('Node', '/turtlesim')
    before = int(zros_cli('param', 'get', '/turtlesim', 'background_r').stdout.split()[-1])
    thumb = browser.wait_for('(() => { const l = [...document.querySelectorAll("label")].find(e => e.innerText.trim()'
                             ' === "background_r"); const s = l && l.closest("div").parentElement'
                             '.querySelector("[role=slider]"); if (!s) return null; s.focus(); return true; })()',
                             timeout=20)
    assert thumb
    for _ in range(5):
        browser.send('Input.dispatchKeyEvent', type='keyDown', key='ArrowRight', code='ArrowRight',
                     windowsVirtualKeyCode=39)
        browser.send('Input.dispatchKeyEvent', type='keyUp', key='ArrowRight', code='ArrowRight',
                     windowsVirtualKeyCode=39)
        time.sleep(0.1)
    wait_until(lambda: int(zros_cli('param', 'get', '/turtlesim', 'background_r').stdout.split()[-1]) == before + 5,
               20, interval=0.5, message='background_r to follow the slider')
    browser.wait_for('document.body.innerText.includes("/turtlesim: background_r = %d")' % (before + 5))
    rqt.shot(tmp_path, 'rqt_parameters.png')
    # A change the node refuses shows its reason, and the page shows the value it kept.
    browser.choose('Node', '/param_talker')
    browser.wait_for('document.body.innerText.includes("published_text")', timeout=20)
    browser.fill('published_text', ' ')
    text = browser.wait_for('(() => { const n = document.querySelector("[data-params=refused]");'
                            ' return n && n.innerText; })()', timeout=20)
    assert 'published_text must not be empty' in text
    page = rqt.page('Parameters')
    wait_until(lambda: page.widgets['published_text'].value == 'Hello World', 20,
               message='the page to show the value the node kept')
