"""Paint on the move: the local paint grid that rides with the brush tip, and paint transfer.

Which model runs is the painting scene's choice (:class:`PaintScene.fluid_model`):

- ``grid3d``: a 3D viscous-fluid grid over the footprint (:mod:`paintapp.paint.grid3d`);
- ``depth_averaged``: a 2D grid in the canvas plane for thin paint
  (:mod:`paintapp.paint.depth_averaged`);
- ``none``: no fluid, the brush stamps and soaks (:mod:`paintapp.paint.stamp`);
- ``auto``: ``depth_averaged`` or ``grid3d`` by the paint layer's thickness, chosen per sample by
  :class:`~paintapp.paint.selector.ModelSelector` (:mod:`paintapp.paint.choice` states the rules,
  :mod:`paintapp.paint.fit` the grid sizing, :mod:`paintapp.paint.fidelity` the presets).
"""
