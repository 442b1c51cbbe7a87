"""Image files as numpy arrays, on Pillow: one codec for maps, cv_bridge, the CLI and the view.

It sits low in the layers (it needs only numpy, Pillow and zros.errors) so that map files,
cv_bridge and `zros image save` read and write images without importing the web view.
Pillow is imported when an image is first encoded or decoded, not when zros is.
"""
from __future__ import annotations

import io

import numpy as np

from zros.errors import ZrosError

__all__ = ['ImageError', 'decode_image', 'encode_png']

#: Pillow's mode for each channel count of an 8-bit array.
_MODES = {1: 'L', 2: 'LA', 3: 'RGB', 4: 'RGBA'}


class ImageError(ZrosError, ValueError):
    """The bytes are not an image Pillow can read, or the pixels cannot be written."""


def encode_png(pixels: np.ndarray, *, level: int = 6) -> bytes:
    """PNG bytes for an (H, W), (H, W, 1), (H, W, 2), (H, W, 3) or (H, W, 4) uint8 array.

    Args:
        pixels: grey, grey+alpha, RGB or RGBA samples, row 0 at the top.
        level: zlib compression level, 0 (none) to 9 (smallest).

    Raises:
        ImageError: the array has another shape or dtype.
    """
    from PIL import Image
    array = np.asarray(pixels)
    if array.dtype != np.uint8:
        raise ImageError(f'encode_png needs uint8 pixels, got {array.dtype}')
    if array.ndim == 2:
        array = array[..., None]
    if array.ndim != 3 or array.shape[2] not in _MODES or 0 in array.shape[:2]:
        raise ImageError(f'encode_png needs an (H, W[, 1|2|3|4]) array, got shape {array.shape}')
    channels = array.shape[2]
    image = Image.fromarray(np.ascontiguousarray(array[..., 0] if channels == 1 else array), _MODES[channels])
    out = io.BytesIO()
    image.save(out, format='PNG', compress_level=level)
    return out.getvalue()


def decode_image(data: bytes) -> np.ndarray:
    """An (H, W, C) array from the bytes of an image file (PNG, PGM/PPM, ...), row 0 at the top.

    C is 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA); palette images come out as RGB, or
    RGBA when they have transparency. Samples are uint8, or uint16 for 16-bit grey images
    (scaled to 0..65535, as Pillow reads a PGM whose maximum is above 255).

    Raises:
        ImageError: not an image, or a truncated or unsupported one.
    """
    from PIL import Image, UnidentifiedImageError
    try:
        with Image.open(io.BytesIO(data)) as image:
            image.load()
            array = _samples(image)
    except UnidentifiedImageError:
        raise ImageError('not an image file Pillow can read') from None
    except (OSError, ValueError, SyntaxError) as exc:   # Pillow's errors for damaged files
        raise ImageError(f'cannot decode the image: {exc}') from None
    return array[..., None] if array.ndim == 2 else array


def _samples(image) -> np.ndarray:
    """The samples of a Pillow image, in one of the layouts decode_image promises."""
    if image.mode in ('I', 'I;16', 'I;16B', 'I;16L'):
        return np.asarray(image).astype(np.uint16)     # Pillow scales 16-bit PGM to 0..65535
    if image.mode not in ('L', 'LA', 'RGB', 'RGBA'):
        alpha = image.mode in ('PA', 'La') or 'transparency' in image.info
        image = image.convert('RGBA' if alpha else ('L' if image.mode == '1' else 'RGB'))
    return np.asarray(image)
