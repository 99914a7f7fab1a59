"""Replays: a recorded run as a glTF 2.0 binary (``.glb``) a browser shows in 3D.

A replay holds the scene's visual shapes (``geometry.py``: meshes with their colours,
primitives tessellated, the floor), one node per moving link, and an animation whose channels
are the recorded poses, reduced within a stated tolerance (``keyframes.py``); ``gltf.py``
writes it with pygltflib and ``export.py`` ties them to a World and a state tape. The page's
viewer (``templates/assets/replay/``) plays it with three.js; Blender and any glTF viewer
open it too. See docs/clips.md, "Replays".
"""
