"""CvBridge: sensor_msgs/Image and CompressedImage <-> numpy arrays shaped as OpenCV's.

An OpenCV image in Python is a numpy array: (H, W) for one channel, (H, W, C) otherwise. The
conversions here need numpy only. Colour changes between the 8- and 16-bit mono, RGB, BGR, RGBA
and BGRA encodings are done in numpy (grey uses OpenCV's weights, so results match
cv2.cvtColor); compressed images use OpenCV when it is installed, and otherwise PNG through
zros's own codec (JPEG then needs `pip install opencv-python-headless`).
"""
from __future__ import annotations

import re
import sys
from typing import Any

import numpy as np

__all__ = ['CvBridge', 'CvBridgeError']


class CvBridgeError(TypeError):
    """A conversion that cannot be done (as cv_bridge.CvBridgeError, a TypeError)."""


# encoding -> (numpy type, channels, channel order among 'RGBA' or None for non-colour data)
_COLOUR = {
    'mono8': ('uint8', 1, 'L'), 'mono16': ('uint16', 1, 'L'),
    'rgb8': ('uint8', 3, 'RGB'), 'bgr8': ('uint8', 3, 'BGR'),
    'rgba8': ('uint8', 4, 'RGBA'), 'bgra8': ('uint8', 4, 'BGRA'),
    'rgb16': ('uint16', 3, 'RGB'), 'bgr16': ('uint16', 3, 'BGR'),
    'rgba16': ('uint16', 4, 'RGBA'), 'bgra16': ('uint16', 4, 'BGRA'),
}
_CV_DEPTHS = {'8U': 'uint8', '8S': 'int8', '16U': 'uint16', '16S': 'int16', '32S': 'int32',
              '32F': 'float32', '64F': 'float64'}
_DEPTH_OF = {v: k for k, v in _CV_DEPTHS.items()}
_CV_TYPE = re.compile(r'^(8U|8S|16U|16S|32S|32F|64F)C([1-4])$')
_BAYER = re.compile(r'^bayer_(rggb|bggr|gbrg|grbg)(8|16)$')
_GREY_WEIGHTS = {'R': 0.299, 'G': 0.587, 'B': 0.114}  # ITU-R BT.601, as cv2.COLOR_*2GRAY


def _layout(encoding: str) -> tuple[str, int, str | None]:
    """(numpy type, channels, colour order) of an encoding; CvBridgeError when unknown."""
    if encoding in _COLOUR:
        return _COLOUR[encoding]
    match = _CV_TYPE.match(encoding)
    if match:
        return _CV_DEPTHS[match.group(1)], int(match.group(2)), None
    match = _BAYER.match(encoding)
    if match:
        return ('uint8' if match.group(2) == '8' else 'uint16'), 1, None
    if encoding in ('yuv422', 'uyvy', 'yuyv', 'UYVY', 'YUYV'):
        return 'uint8', 2, None
    raise CvBridgeError(f'Unrecognized image encoding [{encoding}]')


def _cv_type(array: np.ndarray) -> str:
    depth = _DEPTH_OF.get(array.dtype.name)
    if depth is None:
        raise CvBridgeError(f'Unrecognized numpy type {array.dtype} (OpenCV has no such depth)')
    return f'{depth}C{1 if array.ndim < 3 else array.shape[2]}'


def _convert(image: np.ndarray, source: str, target: str) -> np.ndarray:
    """cv_bridge's cvtColor2 for the mono/RGB/BGR(+A) encodings, 8 and 16 bits."""
    if source == target:
        return image
    if source not in _COLOUR or target not in _COLOUR:
        raise CvBridgeError(f'[{source}] to [{target}] is not a supported conversion '
                            f'(colour encodings: {", ".join(_COLOUR)})')
    src_type, _, src_order = _COLOUR[source]
    dst_type, _, dst_order = _COLOUR[target]
    pixels = image.astype(np.float64).reshape(image.shape[:2] + (-1,))
    named = dict(zip(src_order, np.moveaxis(pixels, -1, 0)))
    if 'L' in named:
        named.update(R=named['L'], G=named['L'], B=named['L'])
    elif 'L' in dst_order:
        named['L'] = sum(weight * named[c] for c, weight in _GREY_WEIGHTS.items())
    named.setdefault('A', np.full(pixels.shape[:2], float(np.iinfo(src_type).max)))  # opaque
    scale = np.iinfo(dst_type).max / np.iinfo(src_type).max
    out = np.stack([named[c] for c in dst_order], axis=-1) * scale
    out = np.clip(np.rint(out), 0, np.iinfo(dst_type).max).astype(dst_type)
    return out[..., 0] if dst_order == 'L' else out


class CvBridge:
    """Converts between ROS image messages and OpenCV-style numpy arrays."""

    def encoding_to_dtype_with_channels(self, encoding: str) -> tuple[str, int]:
        dtype, channels, _ = _layout(encoding)
        return dtype, channels

    def dtype_with_channels_to_cvtype2(self, dtype: Any, n_channels: int) -> str:
        return f'{_DEPTH_OF[np.dtype(dtype).name]}C{n_channels}'

    def imgmsg_to_cv2(self, img_msg: Any, desired_encoding: str = 'passthrough') -> np.ndarray:
        """The pixels of a sensor_msgs/Image: (H, W) or (H, W, C), in native byte order,
        converted to `desired_encoding` unless it is 'passthrough'.

        Raises:
            CvBridgeError: unknown encoding, data shorter than height x step, or no conversion.
        """
        dtype_name, channels, _ = _layout(img_msg.encoding)
        dtype = np.dtype(dtype_name).newbyteorder('>' if img_msg.is_bigendian else '<')
        height, width = int(img_msg.height), int(img_msg.width)
        step = int(img_msg.step) or width * channels * dtype.itemsize
        data = img_msg.data
        raw = np.asarray(data, dtype=np.uint8) if isinstance(data, (list, tuple)) else np.frombuffer(data, np.uint8)
        if raw.size < step * height:
            raise CvBridgeError(f'image data holds {raw.size} bytes, {height} rows of step {step} need {step * height}')
        rows = raw[:step * height].reshape(height, step)[:, :width * channels * dtype.itemsize]
        image = np.ascontiguousarray(rows).view(dtype).reshape((height, width, channels) if channels > 1
                                                               else (height, width))
        image = image.astype(image.dtype.newbyteorder('='))
        if desired_encoding == 'passthrough':
            return image
        return _convert(image, img_msg.encoding, desired_encoding)

    def cv2_to_imgmsg(self, cvim: Any, encoding: str = 'passthrough', header: Any = None) -> Any:
        """A sensor_msgs/Image of `cvim`; 'passthrough' names it by its OpenCV type ('8UC3').

        Raises:
            TypeError: `cvim` is not a numpy array.
            CvBridgeError: `encoding` does not fit the array's type and channels.
        """
        from interfaces.sensor_msgs.msg import Image
        if not isinstance(cvim, (np.ndarray, np.generic)):
            raise TypeError('Your input type is not a numpy array')
        cv_type = _cv_type(cvim)
        if encoding != 'passthrough':
            dtype, channels, _ = _layout(encoding)
            if self.dtype_with_channels_to_cvtype2(dtype, channels) != cv_type:
                raise CvBridgeError(f'encoding specified as {encoding}, but image has incompatible type {cv_type}')
        msg = Image(height=cvim.shape[0], width=cvim.shape[1],
                    encoding=cv_type if encoding == 'passthrough' else encoding)
        if header is not None:
            msg.header = header
        msg.is_bigendian = int(cvim.dtype.byteorder == '>' or (cvim.dtype.byteorder == '=' and sys.byteorder == 'big'))
        data = np.ascontiguousarray(cvim).tobytes()
        msg.step = len(data) // msg.height if msg.height else 0
        msg.data = data
        return msg

    def compressed_imgmsg_to_cv2(self, cmprs_img_msg: Any, desired_encoding: str = 'passthrough') -> np.ndarray:
        """Decode a sensor_msgs/CompressedImage; colour comes out BGR(A) as from cv2.imdecode.

        Raises:
            CvBridgeError: undecodable data, or a JPEG without OpenCV installed.
        """
        data = bytes(np.asarray(cmprs_img_msg.data, dtype=np.uint8)) if isinstance(
            cmprs_img_msg.data, (list, tuple)) else bytes(cmprs_img_msg.data)
        cv2 = _opencv()
        if cv2 is not None:
            image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
            if image is None:
                raise CvBridgeError(f"cannot decode the compressed image (format '{cmprs_img_msg.format}')")
        else:
            image = _decode_png(data, cmprs_img_msg.format)
        if desired_encoding == 'passthrough':
            return image
        source = {2: 'mono8', 3: 'bgr8', 4: 'bgra8'}[image.ndim if image.ndim == 2 else image.shape[2]]
        return _convert(image, source, desired_encoding)

    def cv2_to_compressed_imgmsg(self, cvim: Any, dst_format: str = 'jpg') -> Any:
        """A sensor_msgs/CompressedImage of `cvim` (taken as BGR[A] or grey, as OpenCV does).

        Raises:
            TypeError: `cvim` is not a numpy array.
            CvBridgeError: the format cannot be written (JPEG needs OpenCV).
        """
        from interfaces.sensor_msgs.msg import CompressedImage
        if not isinstance(cvim, (np.ndarray, np.generic)):
            raise TypeError('Your input type is not a numpy array')
        cv2 = _opencv()
        if cv2 is not None:
            ok, encoded = cv2.imencode('.' + dst_format, cvim)
            if not ok:
                raise CvBridgeError(f"OpenCV cannot write '{dst_format}' from an array of type {_cv_type(cvim)}")
            data = encoded.tobytes()
        else:
            data = _encode_png(cvim, dst_format)
        return CompressedImage(format=dst_format, data=data)


def _opencv() -> Any:
    try:
        import cv2
    except ImportError:
        return None
    return cv2


def _no_opencv(fmt: str) -> CvBridgeError:
    return CvBridgeError(f"'{fmt}' images need OpenCV (pip install opencv-python-headless); "
                         "without it zros reads and writes 'png'")


def _encode_png(cvim: np.ndarray, fmt: str) -> bytes:
    from zros.image_io import encode_png
    if fmt.lower() != 'png':
        raise _no_opencv(fmt)
    if cvim.dtype != np.uint8 or (cvim.ndim == 3 and cvim.shape[2] not in (1, 3, 4)):
        raise CvBridgeError(f'PNG without OpenCV needs 8-bit grey, BGR or BGRA pixels, got {_cv_type(cvim)}')
    pixels = cvim if cvim.ndim == 2 or cvim.shape[2] == 1 else cvim[..., [2, 1, 0, 3][:cvim.shape[2]]]
    return encode_png(pixels)


def _decode_png(data: bytes, fmt: str) -> np.ndarray:
    from zros.image_io import ImageError, decode_image
    if not data.startswith(b'\x89PNG'):
        raise _no_opencv(fmt.split(';')[0].strip() or 'compressed')
    try:
        pixels = decode_image(data)
    except ImageError as exc:
        raise CvBridgeError(f'cannot decode the PNG: {exc}') from None
    channels = pixels.shape[2]
    if channels == 1:
        return pixels[..., 0]
    if channels == 2:  # grey + alpha: OpenCV gives BGRA
        grey, alpha = pixels[..., 0], pixels[..., 1]
        return np.stack([grey, grey, grey, alpha], axis=-1)
    return np.ascontiguousarray(pixels[..., [2, 1, 0, 3][:channels]])
