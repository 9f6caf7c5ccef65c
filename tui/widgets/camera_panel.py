"""The camera panel: the latest snapshot (JPEG from the robot, on request) in half-blocks."""
from __future__ import annotations

import cv2
import numpy as np
from rich.text import Text
from textual.widgets import Static

from tui.widgets.map_panel import half_blocks


def jpeg_text(jpeg: bytes, width: int, height: int) -> Text | None:
    """The image fitted to ``width`` x ``height`` characters (2 pixels per character row)."""
    img = cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_COLOR) if jpeg else None
    if img is None:
        return None
    h, w = img.shape[:2]
    scale = min(width / w, 2 * height / h)
    size = (max(1, int(w * scale)), max(2, int(h * scale)) // 2 * 2)
    small = cv2.resize(img, size, interpolation=cv2.INTER_AREA)
    return half_blocks(small[:, :, ::-1])


class CameraPanel(Static):
    def show_jpeg(self, camera: str, jpeg: bytes | None) -> None:
        size = self.content_size
        text = jpeg_text(jpeg or b"", size.width, max(size.height - 1, 1))
        if text is None:
            self.update(f"{camera}: no frame")
            return
        self.update(Text.assemble((f"{camera} camera\n", "bold"), text))
