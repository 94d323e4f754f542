"""The visual range sensor: images in, laser-like scans out.

:class:`VisualRanger` (the paper's column edge filter), :class:`AppearanceRanger` (a learned
model of the floor's look), the fused ranger, the calibrated ground lookup table
(:class:`GroundTable`), lens and mount models, and :class:`Scan` (one frame's readings, with the
scans CSV format).
"""
