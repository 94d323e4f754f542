"""The whole job as ``floorscan run`` does it: configuration, frame sources, the per-frame
:class:`~floorscan.pipeline.mapper.Mapper`, and everything a run writes."""
