"""The camera panel: the latest snapshot (JPEG from the robot, on request) in half-blocks,
redrawn to fit when the panel is resized."""
from __future__ import annotations

import cv2
import numpy as np
from rich.text import Text
from textual.widgets import Static

from tui.halfblocks import half_blocks


def jpeg_text(jpeg: bytes, width: int, height: int) -> Text | None:
    """The image fitted to ``width`` x ``height`` characters (2 pixels per character row),
    keeping its aspect; None when the bytes are not an image."""
    img = cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_COLOR) if jpeg else None
    if img is None:
        return None
    h, w = img.shape[:2]
    scale = min(width / w, 2 * height / h)
    size = (max(1, int(w * scale)), max(2, int(h * scale) // 2 * 2))
    small = cv2.resize(img, size, interpolation=cv2.INTER_AREA)
    return half_blocks(small[:, :, ::-1])


class CameraPanel(Static):
    def __init__(self, hint: str, **kw):
        super().__init__(hint, **kw)
        self._camera: str | None = None
        self._jpeg: bytes | None = None

    def show_jpeg(self, camera: str, jpeg: bytes | None) -> None:
        self._camera, self._jpeg = camera, jpeg
        self._draw()

    def _draw(self) -> None:
        if self._camera is None:
            return
        size = self.content_size
        text = jpeg_text(self._jpeg or b"", max(size.width, 1), max(size.height - 1, 1))
        if text is None:
            self.update(f"{self._camera}: no frame")
            return
        self.update(Text.assemble((f"{self._camera} camera\n", "bold"), text))

    def on_resize(self) -> None:
        self._draw()
