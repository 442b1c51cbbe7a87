"""Drive a headless Chromium over the DevTools protocol: load a page, click, drag, read pixels.

The scene view is a WebGL page, so whether it draws the map where TF puts it, or whether a
drag with the Pose Estimate tool publishes the right pose, can only be checked in a browser.
The tests and benchmarks/view.py use this module for that; it needs Debian's `chromium` and the
`websockets` package (a dependency of viser). Software WebGL is enabled with
`--enable-unsafe-swiftshader`, as on a machine without a GPU.

    with Browser(width=1000, height=700) as browser:
        browser.open(url, wait_for='document.querySelector("canvas")')
        browser.wait_drawn(timeout=20)           # the scene view's displays (a map's texture too)
        pixels = browser.screenshot()            # (H, W, 3) uint8
        browser.drag((400, 300), (460, 300))
"""
from __future__ import annotations

import base64
import itertools
import json
import os
import re
import shutil
import subprocess
import tempfile
import time
from typing import Any, Callable

import numpy as np

from zros.image_io import decode_image, encode_png
from zros.process_group import kill_group

__all__ = ['Browser', 'BrowserError', 'find_chromium', 'one_shot']

# Counts the images a page is decoding: viser's client turns an image node (a map) into a blob URL,
# loads it as a texture and revokes the URL once the texture is made (or failed).
_IMAGE_WATCH = '''(() => {
  const create = URL.createObjectURL, revoke = URL.revokeObjectURL, images = new Set();
  window.__zrosImages = {pending: () => images.size, doneAt: 0};
  URL.createObjectURL = function (object) {
    const url = create.call(URL, object);
    if (object && typeof object.type === 'string' && object.type.startsWith('image/')) images.add(url);
    return url;
  };
  URL.revokeObjectURL = function (url) {
    if (images.delete(url)) window.__zrosImages.doneAt = performance.now();
    return revoke.call(URL, url);
  };
})();'''
DRAWN_SETTLE = 0.6     # [s] drawn-looking this long: a texture made is on screen after viser's 250 ms settle window

_FLAGS = ('--headless', '--no-sandbox', '--disable-gpu', '--enable-unsafe-swiftshader',
          '--disable-background-networking', '--disable-component-update', '--disable-sync',
          '--disable-quic', '--no-first-run', '--hide-scrollbars', '--mute-audio',
          '--disable-background-timer-throttling', '--disable-renderer-backgrounding',
          '--remote-debugging-port=0', '--remote-allow-origins=*')


class BrowserError(RuntimeError):
    """Chromium could not be started, or a DevTools command failed or timed out."""


def find_chromium() -> str | None:
    """The Chromium executable (PATH, then Debian's path), or None."""
    for name in ('chromium', 'chromium-browser', 'google-chrome'):
        path = shutil.which(name)
        if path:
            return path
    return '/usr/bin/chromium' if os.path.exists('/usr/bin/chromium') else None


class Browser:
    """One headless Chromium process with one page, driven over its DevTools websocket.

    Args:
        width, height: the window (and screenshot) size in CSS pixels.
        timeout: seconds for Chromium to start and for each DevTools command.
    Raises:
        BrowserError: Chromium is not installed or did not start.
    """

    def __init__(self, *, width: int = 1200, height: int = 800, timeout: float = 30.0) -> None:
        from websockets.sync.client import connect
        executable = find_chromium()
        if executable is None:
            raise BrowserError('Chromium is not installed (Debian: apt-get install chromium)')
        self.width, self.height, self.timeout = width, height, timeout
        self._profile = tempfile.mkdtemp(prefix='zros-chromium-')
        self._process = subprocess.Popen(
            [executable, *_FLAGS, f'--window-size={width},{height}', f'--user-data-dir={self._profile}',
             'about:blank'],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, start_new_session=True)
        try:
            browser_url = self._devtools_url()
            page_url = self._page_target(browser_url)
            self._socket = connect(page_url, max_size=64 * 1024 * 1024, open_timeout=timeout)
        except Exception:
            self.close()
            raise
        self._ids = itertools.count(1)
        self.events: list[dict[str, Any]] = []
        self.send('Page.enable')
        self.send('Runtime.enable')
        self.send('Page.addScriptToEvaluateOnNewDocument', source=_IMAGE_WATCH)
        self.send('Emulation.setDeviceMetricsOverride', width=width, height=height, deviceScaleFactor=1,
                  mobile=False)

    def _devtools_url(self) -> str:
        deadline = time.monotonic() + self.timeout
        seen = b''
        assert self._process.stderr is not None
        os.set_blocking(self._process.stderr.fileno(), False)
        while time.monotonic() < deadline:
            chunk = self._process.stderr.read() or b''
            seen += chunk
            match = re.search(rb'DevTools listening on (ws://\S+)', seen)
            if match:
                return match.group(1).decode()
            if self._process.poll() is not None:
                break
            time.sleep(0.05)
        raise BrowserError('Chromium did not start: ' + seen.decode(errors='replace')[-500:])

    def _page_target(self, browser_url: str) -> str:
        import urllib.request
        port = browser_url.split('//', 1)[1].split('/', 1)[0]
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            try:
                with urllib.request.urlopen(f'http://{port}/json', timeout=5) as response:
                    targets = json.loads(response.read())
            except OSError:                  # a loaded machine: Chromium answers late, ask again
                time.sleep(0.2)
                continue
            pages = [t for t in targets if t.get('type') == 'page']
            if pages:
                return pages[0]['webSocketDebuggerUrl']
            time.sleep(0.1)
        raise BrowserError('Chromium has no page target')

    # -- the protocol ----------------------------------------------------------------------
    def send(self, method: str, **params: Any) -> dict[str, Any]:
        """Run one DevTools command and return its result.

        Raises:
            BrowserError: the command failed or no answer came within `timeout`.
        """
        ident = next(self._ids)
        self._socket.send(json.dumps({'id': ident, 'method': method, 'params': params}))
        deadline = time.monotonic() + self.timeout
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise BrowserError(f'{method}: no answer within {self.timeout:g} s')
            message = json.loads(self._socket.recv(timeout=remaining))
            if message.get('id') == ident:
                if 'error' in message:
                    raise BrowserError(f"{method}: {message['error'].get('message')}")
                return message.get('result', {})
            if 'method' in message:
                self.events.append(message)

    def evaluate(self, expression: str, *, await_promise: bool = False) -> Any:
        """The value of a JavaScript expression in the page (JSON-serialisable values only)."""
        result = self.send('Runtime.evaluate', expression=expression, returnByValue=True,
                           awaitPromise=await_promise)
        if 'exceptionDetails' in result:
            details = result['exceptionDetails']
            text = details.get('exception', {}).get('description') or details.get('text')
            raise BrowserError(f'JavaScript error: {text}')
        return result.get('result', {}).get('value')

    def wait_for(self, expression: str, timeout: float = 20.0, interval: float = 0.1) -> Any:
        """Poll a JavaScript expression until it is truthy; its value.

        Raises:
            BrowserError: it stayed falsy for `timeout` seconds.
        """
        deadline = time.monotonic() + timeout
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() >= deadline:
                raise BrowserError(f'still false after {timeout:g} s: {expression}')
            time.sleep(interval)

    def open(self, url: str, *, wait_for: str | None = None, timeout: float = 30.0) -> None:
        """Navigate to `url` and wait for the load event (and `wait_for`, if given)."""
        self.send('Page.navigate', url=url)
        self.wait_for('document.readyState === "complete"', timeout)
        if wait_for:
            self.wait_for(f"!!({wait_for})", timeout)

    def wait_drawn(self, timeout: float = 20.0) -> bool:
        """Wait until the scene view in the page has drawn what its displays received, so that a
        screenshot shows it: no display still says it is waiting for its first message, no image
        (a map's texture) is still being decoded, and both held for DRAWN_SETTLE seconds.

        The display statuses come over the same websocket as the scene, but viser's client
        decodes a texture after the message that carried it and draws it on a later frame: a
        screenshot taken when the Map display already says `118 x 108 cells` can miss the map.

        Returns:
            True once drawn; False if `timeout` seconds passed first (the page is as drawn as it got).
        """
        from zros.view.scene.displays.base import WAITING
        check = ('(() => { const w = window.__zrosImages; if (!w || !document.querySelector("canvas")) return false;'
                 ' const waiting = [...document.querySelectorAll("[data-status]")].some(e => e.textContent.trim() === '
                 f'{json.dumps(WAITING)}); return !waiting && w.pending() === 0 '
                 f'&& performance.now() - w.doneAt > {DRAWN_SETTLE * 1000:.0f}; }})()')
        deadline = time.monotonic() + timeout
        since = None
        while time.monotonic() < deadline:
            now = time.monotonic()
            if not self.evaluate(check):
                since = None
            elif since is None:
                since = now
            elif now - since >= DRAWN_SETTLE:
                return True
            time.sleep(0.1)
        return False

    def screenshot(self) -> np.ndarray:
        """The page as (H, W, 3) RGB uint8 pixels."""
        data = self.send('Page.captureScreenshot', format='png')['data']
        return decode_image(base64.b64decode(data))[..., :3]

    def save_screenshot(self, path: str | os.PathLike) -> np.ndarray:
        """Write a PNG screenshot to `path` (to look at) and return its pixels."""
        pixels = self.screenshot()
        with open(path, 'wb') as handle:
            handle.write(encode_png(pixels))
        return pixels

    # -- the mouse -------------------------------------------------------------------------
    def _mouse(self, kind: str, x: float, y: float, *, buttons: int, button: str = 'none') -> None:
        self.send('Input.dispatchMouseEvent', type=kind, x=x, y=y, button=button, buttons=buttons,
                  clickCount=1 if kind != 'mouseMoved' else 0, pointerType='mouse')

    def click(self, x: float, y: float) -> None:
        self._mouse('mouseMoved', x, y, buttons=0)
        self._mouse('mousePressed', x, y, buttons=1, button='left')
        time.sleep(0.05)
        self._mouse('mouseReleased', x, y, buttons=0, button='left')

    def drag(self, start: tuple[float, float], end: tuple[float, float], *, steps: int = 12,
             step_delay: float = 0.03) -> None:
        """Press the left button at `start`, move to `end` in `steps`, release there."""
        (x0, y0), (x1, y1) = start, end
        self._mouse('mouseMoved', x0, y0, buttons=0)
        self._mouse('mousePressed', x0, y0, buttons=1, button='left')
        for i in range(1, steps + 1):
            t = i / steps
            time.sleep(step_delay)
            self._mouse('mouseMoved', x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, buttons=1, button='left')
        time.sleep(0.1)
        self._mouse('mouseReleased', x1, y1, buttons=0, button='left')

    def click_text(self, text: str, *, selector: str = 'button, [role=tab]') -> None:
        """Click (with the mouse, at its middle) the innermost visible `selector` element whose text
        is `text` (a folder's header rather than the folder).

        Raises:
            BrowserError: there is no such element.
        """
        self.click(*self._centre(f'[...document.querySelectorAll({json.dumps(selector)})].filter(e => '
                                 f'e.innerText.trim() === {json.dumps(text)} && e.getClientRects().length).pop()',
                                 f'{selector} with the text {text!r}', timeout=5.0))

    def _labelled(self, label: str) -> str:
        """JavaScript for the visible input whose <label> reads `label`."""
        return (f'[...document.querySelectorAll("label")].filter(l => l.innerText.trim() === {json.dumps(label)})'
                '.map(l => document.getElementById(l.htmlFor) || [...l.closest("div").parentElement'
                '.querySelectorAll("input:not([type=hidden]), textarea")].find(e => e.getClientRects().length))'
                '.find(e => e && e.getClientRects().length)')

    def _centre(self, expression: str, what: str, timeout: float | None = None) -> tuple[float, float]:
        """The middle of the element `expression` finds, scrolled into view, once it has stopped
        moving (a folder that is still opening moves what it holds)."""
        script = (f'(() => {{ const el = {expression}; if (!el) return null; el.scrollIntoView({{block: "center"}});'
                  ' const r = el.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; })()')
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        last = None
        while True:
            found = self.evaluate(script)
            if found and found == last:
                return found[0], found[1]
            if time.monotonic() >= deadline:
                if found:
                    return found[0], found[1]
                raise BrowserError(f'no {what}')
            last = found
            time.sleep(0.15)

    def fill(self, label: str, text: str) -> None:
        """Replace the text of the input labelled `label` as a user types it.

        Raises:
            BrowserError: no such input appeared within `timeout`.
        """
        x, y = self._centre(self._labelled(label), f'input labelled {label!r}')
        self.click(x, y)
        self.evaluate(f'(() => {{ const el = {self._labelled(label)}; el.focus(); el.select(); }})()')
        self.send('Input.insertText', text=text)
        self.send('Input.dispatchKeyEvent', type='keyDown', key='Tab', code='Tab', windowsVirtualKeyCode=9)
        self.send('Input.dispatchKeyEvent', type='keyUp', key='Tab', code='Tab', windowsVirtualKeyCode=9)

    def toggle(self, label: str) -> None:
        """Click the checkbox (or switch) labelled `label`, as a user does.

        Raises:
            BrowserError: no such checkbox appeared within `timeout`.
        """
        self.click(*self._centre(self._labelled(label), f'checkbox labelled {label!r}'))

    def choose(self, label: str, option: str) -> None:
        """Open the dropdown labelled `label` and click its option `option`.

        Raises:
            BrowserError: the dropdown or the option did not appear within `timeout`.
        """
        self.click(*self._centre(self._labelled(label), f'dropdown labelled {label!r}'))
        self.click(*self._centre(f'[...document.querySelectorAll("[role=option]")].find(o => o.innerText.trim() === '
                                 f'{json.dumps(option)})', f'option {option!r} in {label!r}'))

    def frame_rate(self, seconds: float = 3.0) -> float:
        """Frames the page drew per second (requestAnimationFrame callbacks), over `seconds`."""
        script = ('new Promise(done => { let n = 0; const t0 = performance.now();'
                  ' const tick = () => { n++; if (performance.now() - t0 < %d) requestAnimationFrame(tick);'
                  ' else done(n * 1000 / (performance.now() - t0)); }; requestAnimationFrame(tick); })'
                  % int(seconds * 1000))
        return float(self.evaluate(script, await_promise=True))

    def until(self, predicate: Callable[[], Any], timeout: float = 20.0, interval: float = 0.2) -> Any:
        """Poll a Python predicate (often about screenshots) until truthy; its value or None."""
        deadline = time.monotonic() + timeout
        while True:
            value = predicate()
            if value or time.monotonic() >= deadline:
                return value
            time.sleep(interval)

    def close(self) -> None:
        """Stop Chromium (its whole process group) and remove its profile."""
        socket = getattr(self, '_socket', None)
        if socket is not None:
            try:
                socket.close()
            except Exception:  # noqa: BLE001 - the browser may be gone already
                pass
        if self._process.poll() is None:
            kill_group(self._process)
        if self._process.stderr is not None:
            self._process.stderr.close()
        shutil.rmtree(self._profile, ignore_errors=True)

    def __enter__(self) -> 'Browser':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def one_shot(url: str, path: str | os.PathLike, *, timeout: float = 20.0, width: int = 1400,
             height: int = 850) -> bool:
    """Open the scene view at `url` in headless Chromium, wait for its displays to be drawn
    (`Browser.wait_drawn`, at most `timeout` seconds) and write one PNG screenshot to `path`.

    Returns:
        True if everything was drawn before the shot; False if the timeout came first.
    Raises:
        BrowserError: Chromium is missing, or the page did not load within `timeout`.
        OSError: `path` cannot be written.
    """
    with Browser(width=width, height=height) as browser:
        started = time.monotonic()
        browser.open(url, wait_for='document.querySelector("canvas")', timeout=timeout)
        browser.evaluate('document.querySelectorAll(".mantine-Notification-closeButton").forEach(b => b.click())')
        drawn = browser.wait_drawn(max(0.0, timeout - (time.monotonic() - started)))
        browser.save_screenshot(path)
    return drawn
