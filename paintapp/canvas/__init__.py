"""The canvas: the paint model (:mod:`.model`), texel boxes (:mod:`.regions`), canvas files in
OpenEXR (:mod:`.exr`) and PNG previews (:mod:`.preview`)."""
