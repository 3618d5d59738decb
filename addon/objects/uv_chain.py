# SPDX-License-Identifier: GPL-3.0-or-later
"""Where an Image Texture node samples its image: the nodes between a UV map and its Vector input, evaluated
over arrays of UVs.

Models made by others read their images through node chains: the glTF
importer mirrors a MIRRORED_REPEAT texture with Separate XYZ, a Math
ping-pong and Combine XYZ, and applies KHR_texture_transform with a Mapping
node. Painting such an image in the object's raw UVs would put the paint
where the image is not read. ``vector_chain`` follows the chain back to the
UV map and returns it as a function of (N, 2) UVs, so the painter paints
each face where the image is sampled, and the painted material reads its maps
through the same chain's output.

The nodes followed: UV Map, Texture Coordinate (its UV output), Reroute,
Separate XYZ, Combine XYZ, Math, Vector Math (the element-wise operations)
and Mapping (Point, Texture, Vector), with their unlinked inputs as values.
Any other node, or a linked input of these that is not part of the chain,
makes the chain unknown (None): the source is then baked as Blender renders
it.
"""

from typing import Callable, NamedTuple, Optional

import numpy as np

MATH = {
    "ADD": lambda a, b, c: a + b, "SUBTRACT": lambda a, b, c: a - b, "MULTIPLY": lambda a, b, c: a * b,
    "DIVIDE": lambda a, b, c: np.divide(a, b, out=np.zeros_like(a * b), where=b != 0),
    "MULTIPLY_ADD": lambda a, b, c: a * b + c, "ABSOLUTE": lambda a, b, c: np.abs(a),
    "MINIMUM": lambda a, b, c: np.minimum(a, b), "MAXIMUM": lambda a, b, c: np.maximum(a, b),
    "FLOOR": lambda a, b, c: np.floor(a), "CEIL": lambda a, b, c: np.ceil(a),
    "FRACT": lambda a, b, c: a - np.floor(a), "MODULO": lambda a, b, c: np.fmod(a, np.where(b == 0, 1, b)) * (b != 0),
    "FLOORED_MODULO": lambda a, b, c: (a - b * np.floor(a / np.where(b == 0, 1, b))) * (b != 0),
    "WRAP": lambda a, b, c: np.where(b != c, a - (b - c) * np.floor((a - c) / np.where(b == c, 1, b - c)), c),
    "SNAP": lambda a, b, c: np.floor(a / np.where(b == 0, 1, b)) * b,
}
VECTOR_MATH = {"ADD": np.add, "SUBTRACT": np.subtract, "MULTIPLY": np.multiply,
               "DIVIDE": lambda a, b: np.divide(a, b, out=np.zeros_like(a * b), where=b != 0),
               "MINIMUM": np.minimum, "MAXIMUM": np.maximum}
VECTOR_UNARY = {"FRACTION": lambda a: a - np.floor(a), "ABSOLUTE": np.abs, "FLOOR": np.floor, "CEIL": np.ceil}


def _pingpong(a, b):
    """Blender's ping-pong of ``a`` between 0 and ``b`` (b != 0)."""
    b = np.where(b == 0, 1.0, b)
    return np.abs((a - b) - 2 * b * np.floor((a - b) / (2 * b)) - b)


MATH["PINGPONG"] = lambda a, b, c: np.where(b != 0, _pingpong(a, b), 0.0)


class VectorChain(NamedTuple):
    """The chain feeding an Image Texture's Vector input."""

    uv_map: Optional[str]       # the UV map it starts from (None: the one Blender renders with)
    transform: Optional[Callable[[np.ndarray], np.ndarray]]   # (N, 2) UVs -> (N, 2) where the image is read; None: as is
    feed: Optional[tuple]       # (node name, output identifier) of what feeds the Vector input; None: nothing


class Unknown(Exception):
    """A node of the chain that is not followed (module docstring)."""


def vector_chain(image_node):
    """The ``VectorChain`` of the Image Texture ``image_node``, or None when a node of it is not followed."""
    vector = image_node.inputs.get("Vector")
    if vector is None or not vector.links:
        return VectorChain(None, None, None)
    link = vector.links[0]
    maps = set()
    try:
        evaluate = _output(link.from_node, link.from_socket, maps)
    except Unknown:
        return None
    if len(maps) > 1:
        return None
    uv_map = next(iter(maps)) if maps else None
    feed = (link.from_node.name, link.from_socket.identifier)
    if _is_identity(link.from_node):
        return VectorChain(uv_map, None, feed)

    def transform(uv):
        points = np.zeros((len(uv), 3))
        points[:, :2] = uv
        return np.asarray(evaluate(points), np.float64)[:, :2]
    return VectorChain(uv_map, transform, feed)


def _is_identity(node):
    """Whether ``node`` gives the UVs unchanged (a UV Map or Texture Coordinate, through Reroutes)."""
    while node.bl_idname == "NodeReroute" and node.inputs[0].links:
        node = node.inputs[0].links[0].from_node
    return node.bl_idname in ("ShaderNodeUVMap", "ShaderNodeTexCoord")


def _input(socket, maps):
    """A function of the (N, 3) UV points giving ``socket``'s value ((N, 3) for a vector, (N,) for a value)."""
    if socket.links:
        link = socket.links[0]
        if link.is_muted:
            raise Unknown()
        value = _output(link.from_node, link.from_socket, maps)
        if socket.type == "VALUE":
            return lambda p, value=value: _as_value(value(p))
        return lambda p, value=value: _as_vector(value(p))
    constant = np.array(socket.default_value, np.float64) if socket.type != "VALUE" else \
        float(socket.default_value)
    return lambda p: np.broadcast_to(constant, (len(p), 3)) if np.ndim(constant) else np.full(len(p), constant)


def _as_value(value):
    """A vector given to a value input is its average, as Blender converts it."""
    return value.mean(axis=1) if np.ndim(value) == 2 else value


def _as_vector(value):
    return value if np.ndim(value) == 2 else np.repeat(value[:, None], 3, axis=1)


def _output(node, socket, maps):
    """A function of the (N, 3) UV points giving ``node``'s output ``socket``."""
    kind = node.bl_idname
    if node.mute:
        raise Unknown()
    if kind == "NodeReroute":
        if not node.inputs[0].links:
            raise Unknown()
        link = node.inputs[0].links[0]
        return _output(link.from_node, link.from_socket, maps)
    if kind == "ShaderNodeUVMap":
        maps.add(node.uv_map or None)
        return lambda p: p
    if kind == "ShaderNodeTexCoord" and socket.identifier == "UV":
        maps.add(None)
        return lambda p: p
    if kind == "ShaderNodeSeparateXYZ":
        vector, axis = _input(node.inputs[0], maps), "XYZ".index(socket.identifier)
        return lambda p: vector(p)[:, axis]
    if kind == "ShaderNodeCombineXYZ":
        x, y, z = (_input(node.inputs[axis], maps) for axis in range(3))
        return lambda p: np.stack([x(p), y(p), z(p)], axis=1)
    if kind == "ShaderNodeMath" and node.operation in MATH:
        a, b, c = (_input(node.inputs[index], maps) for index in range(3))
        operate, clamp = MATH[node.operation], node.use_clamp
        return lambda p: (np.clip if clamp else lambda v, lo, hi: v)(operate(a(p), b(p), c(p)), 0.0, 1.0)
    if kind == "ShaderNodeVectorMath" and socket.type == "VECTOR":
        a, b = _input(node.inputs[0], maps), _input(node.inputs[1], maps)
        if node.operation in VECTOR_MATH:
            return lambda p: VECTOR_MATH[node.operation](a(p), b(p))
        if node.operation in VECTOR_UNARY:
            return lambda p: VECTOR_UNARY[node.operation](a(p))
        if node.operation == "SCALE":
            scale = _input(node.inputs["Scale"], maps)
            return lambda p: a(p) * scale(p)[:, None]
    if kind == "ShaderNodeMapping":
        return _mapping(node, maps)
    raise Unknown()


def _mapping(node, maps):
    """A Mapping node: Point scales, rotates (XYZ Euler) then translates; Texture is its inverse; Vector skips
    the translation."""
    vector = _input(node.inputs["Vector"], maps)
    if node.vector_type not in ("POINT", "TEXTURE", "VECTOR"):
        raise Unknown()
    for name in ("Location", "Rotation", "Scale"):
        if name in node.inputs and node.inputs[name].links:
            raise Unknown()
    location = np.array(node.inputs["Location"].default_value, np.float64) if "Location" in node.inputs else \
        np.zeros(3)
    rotation = _euler(node.inputs["Rotation"].default_value)
    scale = np.array(node.inputs["Scale"].default_value, np.float64)
    if node.vector_type == "TEXTURE":
        safe = np.where(scale == 0, 1.0, scale)
        return lambda p: ((vector(p) - location) @ rotation) / safe
    moved = location if node.vector_type == "POINT" else np.zeros(3)
    return lambda p: (vector(p) * scale) @ rotation.T + moved


def _euler(angles):
    """The 3x3 matrix of Blender's XYZ Euler ``angles`` (radians): Rz @ Ry @ Rx."""
    x, y, z = angles
    rx = np.array([[1, 0, 0], [0, np.cos(x), -np.sin(x)], [0, np.sin(x), np.cos(x)]])
    ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])
    rz = np.array([[np.cos(z), -np.sin(z), 0], [np.sin(z), np.cos(z), 0], [0, 0, 1]])
    return rz @ ry @ rx
