"""Animated GIF of the plate from a field file written by `examples/scene.rs --field`.

Each frame shows the deformed plate (the displacement at every mesh vertex, interpolated linearly
over the cells, lit from one side), the obstacles (a flat or inclined plane, a tabulated surface,
or each local stop as a post with its footprint at its level), the clamped part of the edge on its
moving base, the contact points in contact, and the time, base position and discrete energy. The vertical axis is
exaggerated by a stated whole factor so that millimetre motions of a 0.4 m plate show; its ticks
are true millimetres.

    python examples/plate_animation.py FIELD.json [--out out/plate.gif] [--fps 20]
"""

import argparse
import json
import pathlib
from collections import Counter

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LightSource  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402
from PIL import Image  # noqa: E402

# Drawing only: depth of the base block behind the clamped edge and its half-height (mm).
BASE_DEPTH_MM = 30.0
BASE_HALF_HEIGHT_MM = 3.0
CONTACT_COLOUR = (228, 26, 28)
# GIF palette size: the frames are flat shades of a few colours, and a small palette keeps the
# file at a few hundred KB (measured: 24 colours, 143 frames of 512 × 352 px, about 400 KB).
PALETTE_COLOURS = 24


def triangles(cells):
    """Cells as triangles: a quadrilateral (0, 1, 2, 3) becomes (0, 1, 2) and (0, 2, 3)."""
    out = []
    for cell in cells:
        out.extend([cell[0], cell[k], cell[k + 1]] for k in range(1, len(cell) - 1))
    return np.array(out)


def boundary_edges(cells):
    """Edges (vertex pairs) that belong to one cell only: the outline of the plate."""
    count = Counter(tuple(sorted(e)) for c in cells for e in zip(c, c[1:] + c[:1]))
    return np.array([e for e, n in count.items() if n == 1])


def obstacle_levels(field):
    """Every level (m) an obstacle of the field takes: its surface at the vertices, or its stops'
    levels (the level alone for a field written before profiles existed)."""
    levels = []
    for side in ("lower", "upper"):
        surface = field.get(f"{side}_surface")
        if surface is not None:
            levels.extend(surface)
        elif field[side] is not None and "stops" not in field:
            levels.append(field[side])
    levels.extend(stop["level"] for stop in field.get("stops", []))
    return levels


def vertical_scale(field):
    """Exaggeration of the vertical axis: the whole number that makes the span of the obstacles
    and the motion look 0.4 times as tall as the plate is long."""
    u = np.array([f["u"] for f in field["frames"]])
    levels = obstacle_levels(field)
    span = max(levels + [u.max()]) - min(levels + [u.min()])
    return max(1, round(0.4 * field["length"] / span))


def stop_artists(stop, z_lo, z_hi):
    """A stop drawn in mm: its footprint at its level and a post from there away from the plate
    (down for the lower obstacle, up for the upper), as (polygons, lines)."""
    level = 1e3 * stop["level"]
    end = z_lo if stop["side"] == "lower" else z_hi
    shape = stop["shape"]
    if shape["kind"] == "point":
        x, y = 1e3 * np.array(shape["centre"])
        return [], [[(x, y, level), (x, y, end)]]
    if shape["kind"] == "disc":
        x, y = 1e3 * np.array(shape["centre"])
        r = 1e3 * shape["radius"]
        angles = np.linspace(0, 2 * np.pi, 24, endpoint=False)
        ring = [(x + r * np.cos(a), y + r * np.sin(a), level) for a in angles]
        return [ring], [[(x, y, level), (x, y, end)]]
    (x0, y0), (x1, y1) = 1e3 * np.array(shape["min"]), 1e3 * np.array(shape["max"])
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return (
        [[(x, y, level) for x, y in corners]],
        [[(x, y, level), (x, y, end)] for x, y in corners],
    )


def clamp_blocks(field, outline, xy, z, x_lo):
    """The base as dark blocks along the clamped parts of each side, at height z (mm), and the
    clamped outline edges as (x0, y0, x1, y1) in mm."""
    clamped = set(field["clamped"])
    lx, ly = 1e3 * field["length"], 1e3 * field["width"]
    edges = [(xy[a], xy[b]) for a, b in outline if a in clamped and b in clamped]
    depth = -x_lo
    blocks = []
    for (xa, ya), (xb, yb) in edges:
        x0, x1, y0, y1 = min(xa, xb), max(xa, xb), min(ya, yb), max(ya, yb)
        if x0 == x1 == 0:
            blocks.append(box(-depth, 0, y0, y1, z - BASE_HALF_HEIGHT_MM, z + BASE_HALF_HEIGHT_MM))
        elif x0 == x1 == lx:
            blocks.append(
                box(lx, lx + 0.2 * depth, y0, y1, z - BASE_HALF_HEIGHT_MM, z + BASE_HALF_HEIGHT_MM)
            )
        elif y0 == y1 == 0:
            blocks.append(
                box(x0, x1, -0.2 * depth, 0, z - BASE_HALF_HEIGHT_MM, z + BASE_HALF_HEIGHT_MM)
            )
        else:
            blocks.append(
                box(x0, x1, ly, ly + 0.2 * depth, z - BASE_HALF_HEIGHT_MM, z + BASE_HALF_HEIGHT_MM)
            )
    return [face for b in blocks for face in b], edges


def box(x0, x1, y0, y1, z0, z1):
    """The six faces of an axis-aligned box, as polygons."""
    c = [[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    faces = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
    return [[c[i] for i in face] for face in faces]


def profile_kind(field, side):
    """A short name of an obstacle's profile: plane, inclined plane, table or its stops."""
    profile = field.get(f"{side}_profile", "flat").strip()
    if profile == "flat":
        return "plane"
    if profile.startswith(("plane", "table")):
        return "inclined plane" if profile.startswith("plane") else "table"
    count = sum(1 for stop in field.get("stops", []) if stop["side"] == side)
    return f"{count} stop{'s' if count != 1 else ''}"


def contact_marks(field, frame, xy, u):
    """Where the contact points in contact are drawn (mm): a vertex at its deflection, a stop's own
    point at the level of the one obstacle over or under it (it lies on it)."""
    px, py, pz = (
        list(xy[frame["contact"], 0]),
        list(xy[frame["contact"], 1]),
        list(u[frame["contact"]]),
    )
    points = field.get("points", [])
    vertices = {tuple(np.round(1e3 * np.array(p), 9)) for p in xy[frame["contact"]]}
    for i in frame.get("contact_points", []):
        x, y = 1e3 * np.array(points[i])
        if (round(x, 9), round(y, 9)) in vertices:
            continue
        heights = [
            (field[side], field[f"{side}_heights"][i])
            for side in ("lower", "upper")
            if field[f"{side}_heights"][i] is not None
        ]
        if len(heights) == 1:
            level, h = heights[0]
            px.append(x)
            py.append(y)
            pz.append(1e3 * (level + h))
    return px, py, pz


def render(field, out_path, fps=20.0):
    """Writes the GIF; returns a dict that summarises what it shows."""
    frames = field["frames"]
    xy = 1e3 * np.array(field["vertices"])
    tri = Triangulation(xy[:, 0], xy[:, 1], triangles(field["cells"]))
    outline = boundary_edges(field["cells"])
    lx, ly = 1e3 * field["length"], 1e3 * field["width"]
    levels = [1e3 * g for g in obstacle_levels(field)]
    u_all = 1e3 * np.array([f["u"] for f in frames])
    z_lo = min(levels + [u_all.min()]) - 2.0
    z_hi = max(levels + [u_all.max()]) + 2.0
    x_lo = -BASE_DEPTH_MM
    scale = vertical_scale(field)
    interval = frames[1]["t"] - frames[0]["t"] if len(frames) > 1 else 0.0

    fig = plt.figure(figsize=(6.4, 4.4), dpi=80)
    ax = fig.add_axes((-0.06, -0.07, 1.1, 1.08), projection="3d", computed_zorder=False)
    ax.set_box_aspect((lx - x_lo, ly, scale * (z_hi - z_lo)), zoom=1.2)
    ax.set(xlim=(x_lo, lx), ylim=(0, ly), zlim=(z_lo, z_hi), yticks=[0, ly])
    ax.set_xlabel("x (mm)", labelpad=-2)
    ax.set_ylabel("y (mm)", labelpad=-2)
    ax.set_zlabel("u (mm)", labelpad=-2)
    ax.tick_params(labelsize=7, pad=0)
    ax.view_init(elev=16, azim=-58)
    for pane in (ax.xaxis.pane, ax.yaxis.pane, ax.zaxis.pane):
        pane.set_facecolor("white")
    # The lower obstacle is drawn before the plate, the upper one after it (both translucent):
    # a surface over the plate, or its stops.
    for side, order in (("lower", 1), ("upper", 5)):
        surface = field.get(f"{side}_surface")
        if surface is None and "stops" not in field and field[side] is not None:
            surface = [field[side]] * len(xy)
        if surface is None:
            continue
        height = 1e3 * np.array(surface)
        polygons = [[(*xy[i], height[i]) for i in t] for t in tri.triangles]
        ax.add_collection3d(
            Poly3DCollection(polygons, facecolor="0.55", edgecolor="none", alpha=0.18, zorder=order)
        )
    for stop in field.get("stops", []):
        polygons, posts = stop_artists(stop, z_lo, z_hi)
        order = 1 if stop["side"] == "lower" else 5
        ax.add_collection3d(
            Poly3DCollection(
                polygons, facecolor="0.35", edgecolor="0.2", alpha=0.6, linewidth=0.6, zorder=order
            )
        )
        ax.add_collection3d(Line3DCollection(posts, colors="0.25", linewidths=2.0, zorder=order))
    # Slow motion: each frame shows for 1/fps s of playback and covers `interval` s of motion.
    slowed = f", slowed {1 / (fps * interval):.0f}×" if interval else ""
    heading = (
        f"{field['element'].capitalize()}, {len(field['cells'])} cells; base "
        f"{1e3 * field['base_amplitude']:g} mm at {field['base_frequency']:g} Hz{slowed}"
    )
    fig.text(0.02, 0.96, heading, fontsize=9)
    profiles = [
        f"{side} {profile_kind(field, side)} at {1e3 * field[side]:+g} mm"
        for side in ("lower", "upper")
        if field[side] is not None
    ]
    clamp = field.get("clamp", "xmin")
    fig.text(
        0.02,
        0.925,
        f"dark blocks: the moving base, clamping {clamp} (black); grey: "
        f"obstacles, {'; '.join(profiles) or 'none'}",
        fontsize=7,
        color="0.3",
    )
    fig.text(
        0.02,
        0.895,
        f"red dots: contact points in contact; vertical scale ×{scale} (ticks in true mm)",
        fontsize=7,
        color="0.3",
    )
    info = fig.text(0.02, 0.85, "", fontsize=8, family="monospace")
    light = LightSource(azdeg=200, altdeg=25)

    images = []
    dynamic = []
    contact_frames = 0
    for frame, u in zip(frames, u_all):
        for artist in dynamic:
            artist.remove()
        z = 1e3 * frame["base"]
        faces, clamped_edges = clamp_blocks(field, outline, xy, z, x_lo)
        base = Poly3DCollection(faces, facecolor="0.35", edgecolor="0.15", linewidth=0.5, zorder=2)
        ax.add_collection3d(base)
        surface = ax.plot_trisurf(
            tri,
            u,
            color="#8fb3de",
            shade=True,
            lightsource=light,
            linewidth=0,
            antialiased=False,
            zorder=3,
        )
        rim = Line3DCollection(
            np.dstack([xy[outline], u[outline]]), colors="0.2", linewidths=0.7, zorder=3.5
        )
        ax.add_collection3d(rim)
        clamp = Line3DCollection(
            [[(a[0], a[1], z), (b[0], b[1], z)] for a, b in clamped_edges],
            colors="black",
            linewidths=2.5,
            zorder=4,
        )
        ax.add_collection3d(clamp)
        px, py, pz = contact_marks(field, frame, xy, u)
        marks = ax.scatter(
            px,
            py,
            pz,
            s=22,
            color=np.array(CONTACT_COLOUR) / 255,
            edgecolor="black",
            linewidth=0.6,
            depthshade=False,
            zorder=4,
        )
        dynamic = [base, surface, rim, clamp, marks]
        contact_frames += bool(len(px))
        info.set_text(
            f"t = {frame['t']:.4f} s   base z = {z:+5.2f} mm   "
            f"E = {frame['energy']:6.3f} J   contact: {len(px):2d} points"
        )
        fig.canvas.draw()
        images.append(np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy())
    plt.close(fig)

    # One palette for every frame (from a sample of them, plus a swatch of the contact colour,
    # which covers few pixels), so that colours do not flicker and Pillow's encoder stores only
    # the pixels that change from one frame to the next.
    swatch = np.broadcast_to(np.array(CONTACT_COLOUR, dtype=np.uint8), (64, *images[0].shape[1:]))
    sample = np.concatenate(images[:: max(1, len(images) // 8)] + [swatch], axis=0)
    palette = Image.fromarray(sample).quantize(
        colors=PALETTE_COLOURS, method=Image.Quantize.MEDIANCUT
    )
    gif = [Image.fromarray(a).quantize(palette=palette, dither=Image.Dither.NONE) for a in images]
    out_path = pathlib.Path(out_path)
    gif[0].save(
        out_path,
        save_all=True,
        append_images=gif[1:],
        duration=round(1000 / fps),
        loop=0,
        optimize=True,
    )
    return {
        "frames": len(frames),
        "t0": frames[0]["t"],
        "t1": frames[-1]["t"],
        "frame_interval": interval,
        "contact_frames": contact_frames,
        "vertical_scale": scale,
        "bytes": out_path.stat().st_size,
    }


def summary(path, s):
    """One line that says what the GIF shows."""
    return (
        f"{path}: {s['frames']} frames, t = {s['t0']:.4f} to {s['t1']:.4f} s every "
        f"{1e3 * s['frame_interval']:.2f} ms, {s['contact_frames']} with contact, vertical "
        f"scale ×{s['vertical_scale']}, {s['bytes'] / 1024:.0f} KB"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("field", help="JSON written by examples/scene.rs --field")
    parser.add_argument("--out", default="out/plate.gif")
    parser.add_argument("--fps", type=float, default=20.0)
    args = parser.parse_args()
    field = json.loads(pathlib.Path(args.field).read_text())
    print(summary(args.out, render(field, args.out, fps=args.fps)))


if __name__ == "__main__":
    main()
