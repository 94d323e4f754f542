"""Known camera intrinsics, read from the files other tools write, so that a calibration only
fits the camera's pose above the floor:

- OpenCV ``cv::FileStorage`` YAML or XML (``calibrateCamera`` samples, ``cv2.FileStorage``):
  ``camera_matrix`` (or ``K`` / ``cameraMatrix``), ``distortion_coefficients`` (or ``D`` /
  ``dist_coeffs`` / ``distCoeffs``), optional ``image_width`` / ``image_height`` and
  ``distortion_model`` (``fisheye`` / ``equidistant`` for ``cv::fisheye``; otherwise four
  coefficients are read as fisheye only with ``fisheye = true``).
- ROS ``camera_info`` YAML (``camera_calibration``'s output): ``image_width``,
  ``image_height``, ``camera_matrix.data``, ``distortion_model`` (``plumb_bob``,
  ``rational_polynomial`` without its last three terms, ``equidistant``),
  ``distortion_coefficients.data``.

>>> k = Intrinsics.pinhole(fx=300, fy=300, cx=159.5, cy=119.5, distortion=[-0.2, 0.05, 0, 0, 0])
>>> k.family.name, k.image_size
('pinhole_k3', None)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence, Tuple

import numpy as np

from .._atomic import PathLike
from ..errors import CalibrationError, FileFormatError, FloorscanError
from ..formats.native_messages import native_messages
from .lens_family import FAMILIES, LensFamily

MIN_FOCAL_PX = 1.0
"""Smallest focal length [px] read from a file (below it a camera sees nothing sharp)."""
MAX_PIXEL_VALUE = 1e6
"""Largest focal length and principal point coordinate [px] read from a file."""
MAX_DISTORTION = 1e4
"""Largest magnitude of a distortion coefficient read from a file."""


@dataclass(frozen=True)
class Intrinsics:
    """A lens family and its parameters (fx, fy, cx, cy, terms), and the image size the
    calibration was for (None when the file does not say)."""

    family: LensFamily
    params: np.ndarray
    image_size: Optional[Tuple[int, int]] = None

    @classmethod
    def pinhole(
        cls, *, fx, fy, cx, cy, distortion: Sequence[float] = (), image_size=None
    ) -> Intrinsics:
        """Pinhole with OpenCV's plumb_bob ``distortion`` (k1, k2, p1, p2[, k3])."""
        d = [float(x) for x in distortion] + [0.0] * (5 - len(distortion))
        if len(d) > 5 and any(abs(x) > 0 for x in d[5:]):
            raise CalibrationError(
                "rational or thin-prism distortion (more than 5 coefficients) is not supported"
            )
        k1, k2, p1, p2, k3 = d[:5]
        fam = FAMILIES["pinhole_k3"]
        # pinhole_k3's order is k1, k2, k3; tangential terms need pinhole_k2p.
        if p1 or p2:
            if k3:
                raise CalibrationError(
                    "plumb_bob with both tangential terms and k3 is not supported; refit "
                    "with k3 = 0"
                )
            fam = FAMILIES["pinhole_k2p"]
            terms = [k1, k2, p1, p2]
        else:
            terms = [k1, k2, k3]
        return cls(fam, np.array([fx, fy, cx, cy, *terms], float), image_size)

    @classmethod
    def fisheye(cls, *, fx, fy, cx, cy, distortion: Sequence[float] = (), image_size=None):
        """OpenCV fisheye (Kannala-Brandt) with ``distortion`` (k1, k2, k3, k4)."""
        d = [float(x) for x in distortion] + [0.0] * (4 - len(distortion))
        return cls(FAMILIES["kb4"], np.array([fx, fy, cx, cy, *d[:4]], float), image_size)

    @classmethod
    def load(cls, path: PathLike) -> Intrinsics:
        """Reads an OpenCV FileStorage YAML/XML or a ROS camera_info YAML file."""
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise FileFormatError(f"cannot read intrinsics {path}: {e}") from None
        if text.lstrip().startswith("%YAML") or text.lstrip().startswith("<?xml"):
            return cls._from_opencv(path)
        return cls._from_ros(path, text)

    @classmethod
    def _from_opencv(cls, path: Path) -> Intrinsics:
        import cv2

        try:
            with native_messages():  # its parser's complaints come back in the error
                return cls._read_opencv(path, cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ))
        except FloorscanError:
            raise
        except (cv2.error, SystemError, ValueError, TypeError, OverflowError) as e:
            # SystemError: OpenCV's bindings report a damaged node's type so
            why = str(e).strip().splitlines()[-1] if str(e).strip() else type(e).__name__
            raise FileFormatError(
                f"{path}: not a readable OpenCV FileStorage file: {why}"
            ) from None

    @classmethod
    def _read_opencv(cls, path: Path, fs) -> Intrinsics:
        def node(*names):
            for n in names:
                nd = fs.getNode(n)
                if not nd.empty():
                    return nd
            return None

        k_node = node("camera_matrix", "K", "cameraMatrix", "Camera_Matrix")
        d_node = node(
            "distortion_coefficients", "D", "dist_coeffs", "distCoeffs", "Distortion_Coefficients"
        )
        if k_node is None:
            raise FileFormatError(f"{path}: no `camera_matrix` (or K) in the file")
        k = k_node.mat()
        d = d_node.mat().ravel() if d_node is not None and d_node.mat() is not None else np.zeros(0)
        size = None
        w, h = node("image_width", "width"), node("image_height", "height")
        if w is not None and h is not None:
            size = (int(w.real()), int(h.real()))
        model_node = node("distortion_model")
        model = model_node.string() if model_node is not None else ""
        fish = node("fisheye")
        is_fisheye = model in ("fisheye", "equidistant", "kannala_brandt") or (
            fish is not None and bool(fish.real())
        )
        fs.release()
        return cls._build(path, k, d, size, is_fisheye)

    @classmethod
    def _from_ros(cls, path: Path, text: str) -> Intrinsics:
        import yaml

        try:
            d = yaml.safe_load(text)
        except yaml.YAMLError as e:
            raise FileFormatError(f"{path}: not YAML: {str(e).splitlines()[0]}") from None
        if not isinstance(d, dict) or "camera_matrix" not in d:
            raise FileFormatError(
                f"{path}: not a ROS camera_info YAML (no `camera_matrix`) nor an OpenCV "
                "FileStorage file (no %YAML:1.0 header)"
            )
        try:
            k = np.array(d["camera_matrix"]["data"], float).reshape(3, 3)
            coeffs = np.array((d.get("distortion_coefficients") or {}).get("data") or [], float)
            size = (int(d["image_width"]), int(d["image_height"])) if "image_width" in d else None
        except (KeyError, TypeError, ValueError) as e:
            raise FileFormatError(f"{path}: malformed camera_info: {e}") from None
        model = str(d.get("distortion_model", "plumb_bob"))
        if model not in ("plumb_bob", "rational_polynomial", "equidistant"):
            raise CalibrationError(f"{path}: distortion model {model!r} is not supported")
        return cls._build(path, k, coeffs, size, model == "equidistant")

    @classmethod
    def _build(cls, path, k, d, size, is_fisheye) -> Intrinsics:
        k = np.asarray(k, float)
        if k.shape != (3, 3) or not np.all(np.isfinite(k)) or k[0, 0] <= 0 or k[1, 1] <= 0:
            raise FileFormatError(f"{path}: camera matrix must be a finite 3 x 3 with fx, fy > 0")
        if not (
            MIN_FOCAL_PX <= min(k[0, 0], k[1, 1])
            and max(k[0, 0], k[1, 1], abs(k[0, 2]), abs(k[1, 2])) <= MAX_PIXEL_VALUE
        ):
            raise FileFormatError(
                f"{path}: camera matrix out of range: fx, fy must lie in [{MIN_FOCAL_PX:g}, "
                f"{MAX_PIXEL_VALUE:g}] px and |cx|, |cy| <= {MAX_PIXEL_VALUE:g} px"
            )
        if abs(k[0, 1]) > 1e-9 * k[0, 0]:
            raise CalibrationError(f"{path}: a skewed camera matrix is not supported")
        d = np.asarray(d, float)
        if not np.all(np.isfinite(d)) or np.any(np.abs(d) > MAX_DISTORTION):
            raise FileFormatError(
                f"{path}: distortion coefficients must be finite, each within +-{MAX_DISTORTION:g}"
            )
        kw = dict(
            fx=k[0, 0], fy=k[1, 1], cx=k[0, 2], cy=k[1, 2], distortion=list(d), image_size=size
        )
        return cls.fisheye(**kw) if is_fisheye else cls.pinhole(**kw)

    def check_size(self, image_size: Tuple[int, int]) -> None:
        """Refuses images of another size than the intrinsics were calibrated for."""
        if self.image_size is not None and tuple(self.image_size) != tuple(image_size):
            raise CalibrationError(
                f"the intrinsics are for {self.image_size[0]} x {self.image_size[1]} images, "
                f"the pattern image is {image_size[0]} x {image_size[1]} (rescale the "
                "intrinsics or use the camera's calibration resolution)"
            )
