"""Drawing helpers shared by the examples' figures (matplotlib, imported when called)."""


def draw_slice(ax, atoms, y0, half_width, colour, cmap, clim=None):
    """Spheres whose centres lie within half_width of the plane y = y0, drawn as their x-z
    circles, coloured by colour(atom)."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    inside = [a for a in atoms if abs(a["y"] - y0) < half_width]
    coll = PatchCollection([Circle((a["x"], a["z"]), a["radius"]) for a in inside], cmap=cmap)
    coll.set_array([colour(a) for a in inside])
    if clim:
        coll.set_clim(*clim)
    ax.add_collection(coll)
    ax.set_aspect("equal")
    return coll
