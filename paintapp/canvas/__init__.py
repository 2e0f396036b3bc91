"""The canvas: the paint model (:mod:`.model`), texel boxes (:mod:`.regions`), canvas sizes by
name or in millimetres (:mod:`.sizes`), canvas files in OpenEXR (:mod:`.exr`), PNG previews
(:mod:`.preview`), and how strongly an image carries a texel lattice (:mod:`.lattice`)."""
