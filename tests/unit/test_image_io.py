"""zros.image_io: PNG out, PNG/PGM/palette images in, as the arrays maps and cv_bridge use."""
from __future__ import annotations

import io

import numpy as np
import pytest

from zros.image_io import ImageError, decode_image, encode_png


@pytest.mark.parametrize('shape', [(7, 5), (7, 5, 1), (9, 4, 2), (13, 11, 3), (3, 17, 4)])
def test_png_round_trip(shape):
    rng = np.random.default_rng(len(shape) * 31 + shape[0])
    pixels = rng.integers(0, 256, size=shape, dtype=np.uint8)
    data = encode_png(pixels)
    assert data[:8] == b'\x89PNG\r\n\x1a\n'
    back = decode_image(data)
    assert back.dtype == np.uint8
    assert back.shape == (shape[0], shape[1], shape[2] if len(shape) == 3 else 1)
    assert (back.reshape(pixels.shape) == pixels).all()


def test_pgm_8_and_16_bit_samples_span_their_dtype():
    grey = decode_image(b'P5\n3 1\n255\n\x00\x7f\xff')
    assert grey.dtype == np.uint8 and grey[..., 0].tolist() == [[0, 127, 255]]
    deep = decode_image(b'P5\n2 1\n1000\n' + np.array([0, 1000], dtype='>u2').tobytes())
    assert deep.dtype == np.uint16 and deep[..., 0].tolist() == [[0, 65535]]
    plain = decode_image(b'P2\n2 1\n255\n0 254\n')
    assert plain[..., 0].tolist() == [[0, 254]]


def test_palette_with_transparency_comes_out_rgba():
    from PIL import Image
    image = Image.new('P', (2, 1))
    image.putpalette([10, 20, 30, 40, 50, 60])
    image.putdata([0, 1])
    out = io.BytesIO()
    image.save(out, format='PNG', transparency=0)
    pixels = decode_image(out.getvalue())
    assert pixels.shape == (1, 2, 4)
    assert pixels[0, 0].tolist() == [10, 20, 30, 0] and pixels[0, 1].tolist() == [40, 50, 60, 255]


@pytest.mark.parametrize('data', [b'GIF89a', b'', encode_png(np.zeros((4, 4), dtype=np.uint8))[:30]])
def test_unreadable_bytes_are_one_image_error(data):
    with pytest.raises(ImageError):
        decode_image(data)


@pytest.mark.parametrize('pixels', [np.zeros((4, 4), dtype=np.float32), np.zeros((4, 4, 5), dtype=np.uint8),
                                    np.zeros((0, 4), dtype=np.uint8)])
def test_encode_rejects_what_png_cannot_hold(pixels):
    with pytest.raises(ImageError, match='encode_png needs'):
        encode_png(pixels)
