"""Figure-ground in photographs: which pixels are the object.

``photo`` (the automatic method and its hypotheses), ``boxcut`` (one box
per object), ``grabcut`` (OpenCV's GrabCut, seeded), ``colour_edge``
(colour edges for the outline's last pixel), ``assists`` (boxes and
scribbles a user draws), ``model`` (a raw ONNX salient-object network) and
``learned`` (networks through rembg).
"""
