"""A minimal one-page vector PDF writer (zlib only): drawings out of zros without
Graphviz, Cairo or a PDF library.

`PdfPage` takes SVG's coordinates (origin top-left, y down, 1 unit = 1 pt) and draws lines,
arrow heads, ellipses, rectangles and text in the standard Helvetica font, which every PDF
viewer has, so nothing is embedded. Text is Latin-1; other characters print as '?'. Widths for
centred text are Helvetica's average, good enough for labels. It is meant for diagrams such
as view_frames' tree, not as a general PDF library.
"""
from __future__ import annotations

import math
import zlib

__all__ = ['PdfPage']

# Bezier control distance that makes four cubic curves a circle of radius 1.
_KAPPA = 4.0 * (math.sqrt(2.0) - 1.0) / 3.0
# Helvetica's mean advance width of common text, in ems (for centring).
_HELVETICA_EM = 0.55
_ARROW_LENGTH = 8.0   # [pt]
_ARROW_HALF_WIDTH = 3.5   # [pt]


class PdfPage:
    """One page; draw on it, then `to_bytes()` gives the whole file."""

    def __init__(self, width: float, height: float) -> None:
        self.width, self.height = float(width), float(height)
        self._ops: list[str] = ['1 1 1 rg 0 0 0 RG 1 w', f'0 0 {self.width:.2f} {self.height:.2f} re f', '0 0 0 rg']

    def _xy(self, x: float, y: float) -> str:
        return f'{x:.2f} {self.height - y:.2f}'

    def polyline(self, points: list[tuple[float, float]], *, arrow: bool = False) -> None:
        """Straight segments through `points`; `arrow` puts a filled head at the last point."""
        (x0, y0), rest = points[0], points[1:]
        self._ops.append(f'{self._xy(x0, y0)} m ' + ' '.join(f'{self._xy(x, y)} l' for x, y in rest) + ' S')
        if arrow and len(points) >= 2:
            (xa, ya), (xb, yb) = points[-2], points[-1]
            length = math.hypot(xb - xa, yb - ya) or 1.0
            ux, uy = (xb - xa) / length, (yb - ya) / length
            bx, by = xb - ux * _ARROW_LENGTH, yb - uy * _ARROW_LENGTH
            left = (bx - uy * _ARROW_HALF_WIDTH, by + ux * _ARROW_HALF_WIDTH)
            right = (bx + uy * _ARROW_HALF_WIDTH, by - ux * _ARROW_HALF_WIDTH)
            self._ops.append(f'{self._xy(xb, yb)} m {self._xy(*left)} l {self._xy(*right)} l h f')

    def rect(self, x: float, y: float, width: float, height: float, *, line_width: float = 1.0) -> None:
        """An unfilled rectangle with its top-left corner at (x, y)."""
        self._ops.append(f'{line_width:.2f} w {x:.2f} {self.height - y - height:.2f} {width:.2f} {height:.2f} re S 1 w')

    def ellipse(self, cx: float, cy: float, rx: float, ry: float) -> None:
        """A white ellipse with a black outline (covers what was drawn under it)."""
        kx, ky = rx * _KAPPA, ry * _KAPPA
        points = [(cx + rx, cy), (cx + rx, cy - ky), (cx + kx, cy - ry), (cx, cy - ry), (cx - kx, cy - ry),
                  (cx - rx, cy - ky), (cx - rx, cy), (cx - rx, cy + ky), (cx - kx, cy + ry), (cx, cy + ry),
                  (cx + kx, cy + ry), (cx + rx, cy + ky), (cx + rx, cy)]
        path = [f'{self._xy(*points[0])} m']
        for i in range(1, 13, 3):
            path.append(' '.join(self._xy(*p) for p in points[i:i + 3]) + ' c')
        self._ops.append('1 1 1 rg ' + ' '.join(path) + ' b 0 0 0 rg')

    def text(self, x: float, y: float, text: str, size: float, *, anchor: str = 'start') -> None:
        """`text` with its baseline at y; `anchor` 'start' or 'middle' (at x), as SVG's text-anchor."""
        if anchor == 'middle':
            x -= len(text) * size * _HELVETICA_EM / 2.0
        raw = text.encode('latin-1', 'replace').decode('latin-1')
        escaped = raw.replace('\\', '\\\\').replace('(', '\\(').replace(')', '\\)')
        self._ops.append(f'BT /F1 {size:.2f} Tf {self._xy(x, y)} Td ({escaped}) Tj ET')

    def to_bytes(self) -> bytes:
        """The PDF file: catalog, page tree, page, font and the compressed drawing."""
        content = zlib.compress('\n'.join(self._ops).encode('latin-1'))
        objects = [
            b'<< /Type /Catalog /Pages 2 0 R >>',
            b'<< /Type /Pages /Kids [3 0 R] /Count 1 >>',
            (f'<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {self.width:.2f} {self.height:.2f}] '
             '/Resources << /Font << /F1 4 0 R >> >> /Contents 5 0 R >>').encode(),
            b'<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>',
            f'<< /Length {len(content)} /Filter /FlateDecode >>\nstream\n'.encode() + content + b'\nendstream',
        ]
        out = bytearray(b'%PDF-1.4\n%\xe2\xe3\xcf\xd3\n')
        offsets = []
        for number, body in enumerate(objects, start=1):
            offsets.append(len(out))
            out += f'{number} 0 obj\n'.encode() + body + b'\nendobj\n'
        xref = len(out)
        out += f'xref\n0 {len(objects) + 1}\n0000000000 65535 f \n'.encode()
        out += b''.join(f'{offset:010d} 00000 n \n'.encode() for offset in offsets)
        out += f'trailer\n<< /Size {len(objects) + 1} /Root 1 0 R >>\nstartxref\n{xref}\n%%EOF\n'.encode()
        return bytes(out)
