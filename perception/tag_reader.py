"""The AprilTag 36h11 reader for front-camera frames: id, pose and off-axis angle.

OpenCV's ArUco module decodes AprilTag 36h11 (``DICT_APRILTAG_36h11``, the dictionary the sim
prints its plates from) on a grey image, so ink colour does not matter as long as it is dark
against a light card: the sim's navy on pale blue (grey ~39 on ~190) and real black on white
read alike.
Corners are refined to sub-pixel (the AprilTag refinement is far slower, reference/upstream.md).

Ids outside the whitelist (upstream: 0..21) are dropped. The pose is ``cv2.solvePnP`` on the
four corners of a ``tag_size`` square and the camera's intrinsics (data from config: a
calibration on the robot, the field of view in the sim), solved with ``SOLVEPNP_SQPNP`` (a
global solver). Not IPPE_SQUARE, the textbook choice for a square: in the OpenCV 5.0 we build
on it returns rotations with reprojection errors of 15-250 px on clean, exactly square corners
(tests/perception/test_tag_reader.py pins the solver we use against ground truth). The off-axis angle
(tag normal against the line back to the camera) tells the mission whether it read the tag
head-on, which is what the seed's tight 0.12 rad yaw tolerance is for.
"""
from __future__ import annotations

import math

import cv2
import numpy as np

from perception.config import TagConfig
from perception.detections import TagRead
from perception.frames import as_gray

_DICTIONARY = cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_APRILTAG_36h11)


def _object_points(size: float) -> np.ndarray:
    """Tag corners in the tag frame (x right, y up, z out of the face), in ArUco's corner order
    (top-left, top-right, bottom-right, bottom-left)."""
    h = size / 2.0
    return np.array([[-h, h, 0.0], [h, h, 0.0], [h, -h, 0.0], [-h, -h, 0.0]], dtype=np.float64)


def off_axis_angle(rvec: np.ndarray, tvec: np.ndarray) -> float:
    """Angle between the tag's normal and the direction from the tag to the camera, rad."""
    normal = cv2.Rodrigues(np.asarray(rvec, np.float64))[0][:, 2]
    t = np.asarray(tvec, np.float64).ravel()
    cos = float(np.dot(normal, -t) / max(np.linalg.norm(t), 1e-12))
    return math.acos(max(-1.0, min(1.0, cos)))


class TagReader:
    def __init__(self, config: TagConfig | None = None):
        self.config = c = config or TagConfig()
        params = cv2.aruco.DetectorParameters()
        if c.subpixel:
            params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_SUBPIX
        self._detector = cv2.aruco.ArucoDetector(_DICTIONARY, params)
        self._whitelist = frozenset(c.whitelist)
        self._object = _object_points(c.tag_size)
        self._k = c.camera.matrix()
        self._dist = c.camera.dist_coeffs()
        self._size = (c.camera.width, c.camera.height)

    def camera_matrix(self, width: int, height: int) -> np.ndarray:
        """K for a frame of this size: the configured camera's, scaled when the frame is a
        resized copy (a saved thumbnail, a photo) of a different size than configured."""
        if (width, height) == self._size:
            return self._k
        k = self._k.copy()
        sx, sy = width / self._size[0], height / self._size[1]
        k[0, 0] *= sx
        k[1, 1] *= sy
        k[0, 2] = (k[0, 2] + 0.5) * sx - 0.5
        k[1, 2] = (k[1, 2] + 0.5) * sy - 0.5
        return k

    def read(self, frame: object) -> tuple[TagRead, ...]:
        """Whitelisted tags in a frame, nearest first; nothing for an unusable frame."""
        gray = as_gray(frame)
        if gray is None:
            return ()
        corners, ids = self._decode(gray)
        k = self.camera_matrix(gray.shape[1], gray.shape[0])
        reads = [self._pose(int(i), c.reshape(4, 2), k) for c, i in zip(corners, ids)
                 if int(i) in self._whitelist]
        return tuple(sorted((r for r in reads if r is not None), key=lambda r: r.distance))

    __call__ = read

    def _decode(self, gray: np.ndarray):
        corners, ids, _ = self._detector.detectMarkers(gray)
        if ids is None:
            return (), ()
        return corners, ids.ravel()

    def _pose(self, tag_id: int, corners: np.ndarray, k: np.ndarray) -> TagRead | None:
        image = corners.astype(np.float64)
        try:
            n, rvecs, tvecs, errors = cv2.solvePnPGeneric(
                self._object, image, k, self._dist, flags=cv2.SOLVEPNP_SQPNP)
        except cv2.error:
            return None
        if n == 0:
            return None
        rvec, tvec = rvecs[0].ravel(), tvecs[0].ravel()
        if tvec[2] <= 0 or not (np.all(np.isfinite(tvec)) and np.all(np.isfinite(rvec))):
            return None
        return TagRead(id=tag_id,
                       corners=tuple((float(x), float(y)) for x, y in corners),
                       position=(float(tvec[0]), float(tvec[1]), float(tvec[2])),
                       rotation=(float(rvec[0]), float(rvec[1]), float(rvec[2])),
                       off_axis=off_axis_angle(rvec, tvec),
                       reprojection_px=float(np.asarray(errors).ravel()[0]))
