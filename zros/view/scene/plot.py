"""The samples behind rqt_plot's page: every series at its own times, decimated for the browser.

A topic plotted at 50 Hz (or 1 kHz) costs the page the same: `PlotBuffer.window` reduces what
is sent to at most `points` samples per series on one shared time axis (bin means, with empty
bins interpolated), while the CSV export writes every sample received.
"""
from __future__ import annotations

import io
import threading
from collections import deque

import numpy as np

__all__ = ['PlotBuffer']


class PlotBuffer:
    """Samples (time [s], value) per series name, the last `keep` seconds of each."""

    def __init__(self, keep: float = 300.0) -> None:
        self.keep = keep
        self._series: dict[str, deque[tuple[float, float]]] = {}
        self._lock = threading.Lock()

    def add(self, name: str, t: float, value: float) -> None:
        with self._lock:
            samples = self._series.setdefault(name, deque())
            samples.append((t, value))
            while samples and t - samples[0][0] > self.keep:
                samples.popleft()

    def remove(self, name: str) -> None:
        with self._lock:
            self._series.pop(name, None)

    def clear(self) -> None:
        with self._lock:
            for samples in self._series.values():
                samples.clear()

    def count(self, name: str) -> int:
        with self._lock:
            return len(self._series.get(name, ()))

    def last(self, name: str) -> float | None:
        with self._lock:
            samples = self._series.get(name)
            return samples[-1][1] if samples else None

    def arrays(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        with self._lock:
            samples = list(self._series.get(name, ()))
        if not samples:
            return np.empty(0), np.empty(0)
        data = np.asarray(samples, dtype=np.float64)
        return data[:, 0], data[:, 1]

    def window(self, names: list[str], start: float, end: float, points: int = 500) -> tuple[np.ndarray, ...]:
        """(x, y_1, ..., y_n) on one time axis over [start, end], at most `points` long.

        With few samples the axis is their union (exact); otherwise `points` bins whose value
        is the mean of the samples in it. The axis starts at the first sample; a series holds its
        first and last values outside its own samples (the browser's uPlot takes no NaN).
        """
        series = []
        for name in names:
            t, v = self.arrays(name)
            keep = (t >= start) & (t <= end)
            series.append((t[keep], v[keep]))
        total = np.unique(np.concatenate([t for t, _ in series])) if series else np.empty(0)
        if total.size == 0:
            return (np.empty(0), *(np.empty(0) for _ in names))
        start = max(start, float(total[0]))
        if total.size <= points:
            x = total
            ys = [_interp(x, t, v) for t, v in series]
        else:
            edges = np.linspace(start, end, points + 1)
            x = (edges[:-1] + edges[1:]) / 2
            ys = []
            for t, v in series:
                bins = np.clip(np.searchsorted(edges, t, side='right') - 1, 0, points - 1)
                counts = np.bincount(bins, minlength=points)
                sums = np.bincount(bins, weights=v, minlength=points)
                filled = counts > 0
                ys.append(_interp(x, x[filled], sums[filled] / counts[filled]))
        return (x, *ys)

    def to_csv(self, names: list[str]) -> str:
        """Every sample: a `time` column and one per series (empty where a series has no sample
        at that time; fields of one message share their rows)."""
        columns = {name: dict(zip(*(a.tolist() for a in self.arrays(name)))) for name in names}
        times = sorted({t for values in columns.values() for t in values})
        out = io.StringIO()
        out.write(','.join(['time', *names]) + '\n')
        for t in times:
            cells = [repr(columns[name][t]) if t in columns[name] else '' for name in names]
            out.write(f'{t:.6f},' + ','.join(cells) + '\n')
        return out.getvalue()


def _interp(x: np.ndarray, t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """`v(t)` at `x`, linear between samples, the edge values outside them (zeros if none)."""
    if t.size == 0:
        return np.zeros(x.shape)
    return np.interp(x, t, v)
