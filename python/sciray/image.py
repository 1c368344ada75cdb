"""Images that show themselves in Jupyter."""
import numpy as np

from . import _sciray


def to_srgb8(linear):
    """Linear RGB(A) floats as 8-bit sRGB (alpha stays linear)."""
    a = np.clip(np.asarray(linear, dtype=np.float32), 0.0, 1.0)
    out = a.copy()
    rgb = out[..., :3]
    rgb[...] = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(rgb, 1 / 2.4) - 0.055)
    return np.round(out * 255.0).astype(np.uint8)


class Image(np.ndarray):
    """A rendered image, (height, width, 4), top row first: a numpy array that Jupyter shows
    as a PNG and that `save` writes as one."""

    def __new__(cls, array):
        return np.asarray(array).view(cls)

    def png(self):
        """The image encoded as PNG bytes (float images as sRGB)."""
        a = np.asarray(self)
        if a.ndim == 2:
            a = a[..., np.newaxis]
        if a.dtype != np.uint8:
            a = to_srgb8(a)
        return _sciray._encode_png(np.ascontiguousarray(a))

    def _repr_png_(self):
        if self.ndim not in (2, 3):
            return None
        return self.png()

    def save(self, path):
        with open(path, "wb") as f:
            f.write(self.png())
