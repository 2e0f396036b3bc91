"""Paint on the move: the local paint grid that rides with the brush tip, and paint transfer.

Which model runs is the painting scene's choice (:class:`PaintScene.fluid_model`):

- ``grid3d``: a 3D viscous-fluid grid over the footprint (:mod:`paintapp.paint.grid3d`);
- ``depth_averaged``: a 2D grid in the canvas plane for thin paint (:mod:`.depth_averaged`);
- ``none``: no fluid, the brush stamps and soaks (:mod:`paintapp.paint.stamp`);
- ``auto``: ``depth_averaged`` or ``grid3d`` by the paint layer's thickness, chosen per sample by
  :class:`~paintapp.paint.selector.ModelSelector` (:mod:`paintapp.paint.choice` states the rules,
  :mod:`paintapp.paint.fit` the grid sizing, :mod:`paintapp.paint.fidelity` the presets).

Shared: the scene files (:mod:`.paint_scene`); following the tip, the canvas window and split steps
(:mod:`.paint_model`); the grid's columns on the canvas and column/texel transfer (:mod:`.columns`,
kernels :mod:`.columns_kernels`, the sweep's water-filling :mod:`.water_filling`, the share sweep
:mod:`.share_sweep` and its exponents :mod:`.kept_share`); brush/cell paint exchange
(:mod:`.exchange`, kernels :mod:`.cell_kernels`), pushed paint (:mod:`.nearest_room`), the bristle texture (:mod:`.bristles`),
the tip's trail (:mod:`.trail`); the 3D grid's open sides (:mod:`.far_field`); the wet paint moved
on the texels by the grid's flow (:mod:`.wet_flow`; flow on texel faces :mod:`.texel_velocity`,
transport kernels :mod:`.wet_flow_kernels`).
"""
