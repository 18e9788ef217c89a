"""Command line of the post-processing: `render` and `report` (run by `skred render` and
`skred report`, which check their options first and pass them on unchanged)."""
import argparse
import os
import sys

from .data import PostError, View, frames_index, load_frame


def field_slug(style):
    return style.pattern or style.field.replace(":", "_")


def cmd_sweep(a):
    from .render import save
    from .sweep import plot_sweep
    out = a.output or os.path.join(a.outdir, "pictures", "sweep.png")
    save(plot_sweep(a.outdir, dpi=a.dpi), out)
    print(f"wrote {out}")
    return 0


def cmd_refine(a):
    from .render import save
    from .refine import plot_refine
    out = a.output or os.path.join(a.outdir, "pictures", "refine.png")
    save(plot_refine(a.outdir, dpi=a.dpi), out)
    print(f"wrote {out}")
    return 0


def cmd_fos(a):
    from .render import save
    from .fos import plot_fos
    out = a.output or os.path.join(a.outdir, "pictures", "fos.png")
    save(plot_fos(a.outdir, dpi=a.dpi), out)
    print(f"wrote {out}")
    return 0


def cmd_render(a):
    from .render import Style, bounds, check_style, draw_frame, save
    from .data import slip_circle_of
    from .scenario_info import body_names_of
    import matplotlib
    if a.cmap not in matplotlib.colormaps:
        raise PostError(f"unknown colour map '{a.cmap}'; e.g. viridis, plasma, coolwarm, RdBu_r")
    pattern = "stripes" if a.stripes else "checkerboard" if a.checkerboard else None
    style = Style(field=a.field, cmap=a.cmap, vrange=tuple(a.range) if a.range else None,
                  pattern=pattern, pattern_width=a.pattern_width, pattern_angle=a.pattern_angle,
                  arrows=a.arrows, crosses=a.crosses, sample=a.sample, dpi=a.dpi,
                  body_names=body_names_of(a.outdir),
                  slip_circle=slip_circle_of(a.outdir) if a.slip_circle else None)
    pictures = os.path.join(a.outdir, "pictures")
    view = View(kind=a.view, z=a.section_z, width=a.slab)  # 3D frames only
    if a.series:
        from .series import plot_series
        out = a.output or os.path.join(pictures, "series.png")
        save(plot_series(a.outdir, dpi=a.dpi), out)
        print(f"wrote {out}")
        return 0
    if a.all:
        from .animate import render_all
        from .render import resolve_field
        if not style.pattern and not style.field:  # the default field names the GIF
            resolve_field(load_frame(a.outdir, -1, view), style)
        out = a.output or os.path.join(pictures, field_slug(style) + ".gif")
        render_all(a.outdir, style, out, fps=a.fps, view=view, info_path=a.info)
        return 0
    if a.map:
        if a.view != "top":
            raise PostError("--map draws a map seen from above: add --view top")
        from .maps import plot_map
        out = a.output or os.path.join(pictures, f"map_{a.map}.png")
        save(plot_map(a.outdir, a.map, dpi=a.dpi, cmap=a.cmap if a.cmap != "viridis" else None,
                      vrange=tuple(a.range) if a.range else None), out)
        print(f"wrote {out}")
        return 0
    frame = load_frame(a.outdir, a.step, view)
    check_style(frame, style)  # also picks the default field
    xlim, ylim = bounds([frame])
    fig, info = draw_frame(frame, style, xlim, ylim)
    out = a.output or os.path.join(pictures, f"{field_slug(style)}_{frame.step:06}.png")
    save(fig, out, info, a.info)
    print(f"wrote {out}")
    return 0


def cmd_report(a):
    from .report import write_report
    if not frames_index(a.outdir):
        raise PostError(f"{a.outdir}/particles.pvd lists no frames")
    out = a.output or os.path.join(a.outdir, "report.html")
    write_report(a.outdir, out, a.field)
    print(f"wrote {out}")
    return 0


def parser():
    p = argparse.ArgumentParser(prog="skred", description="skred post-processing")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render", help="PNG of a frame, GIF of all frames, or the time series")
    r.add_argument("outdir")
    r.add_argument("--field", help="NAME or NAME:COMPONENT (default: displacement, its magnitude)")
    g = r.add_mutually_exclusive_group()
    g.add_argument("--step", type=int, default=-1, help="frame number (default: the last)")
    g.add_argument("--all", action="store_true", help="every frame, and an animated GIF")
    g.add_argument("--series", action="store_true", help="the series.csv plots")
    r.add_argument("-o", "--output")
    r.add_argument("--arrows", action="store_true")
    r.add_argument("--crosses", action="store_true")
    r.add_argument("--slip-circle", action="store_true",
                   help="summary.json's limit-equilibrium slip circle (Bishop's F), dashed")
    pat = r.add_mutually_exclusive_group()
    pat.add_argument("--stripes", action="store_true")
    pat.add_argument("--checkerboard", action="store_true")
    r.add_argument("--pattern-width", type=float, help="stripe width [m] (default: 4 voxels)")
    r.add_argument("--pattern-angle", type=float, default=0.0, help="stripe direction [deg]")
    r.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"),
                   help="colour range in the colour bar's unit (kPa for stresses)")
    r.add_argument("--cmap", default="viridis")
    r.add_argument("--sample", type=int, default=4, help="overlays: 1 particle per N x N voxels")
    r.add_argument("--fps", type=float, default=8.0)
    r.add_argument("--dpi", type=int, default=100)
    r.add_argument("--info", help="write where the axes and colour bar are (JSON)")
    r.add_argument("--view", choices=["section", "top"], default="section",
                   help="3D runs: a section z = const (default) or the surface seen from above")
    r.add_argument("--section-z", type=float, help="3D section: z of the plane [m] (default: mid material)")
    r.add_argument("--map", help="3D runs with --view top: the hazard map NAME (maps/NAME.asc) "
                   "over a hillshade, with a scale bar and the runout outline")
    r.add_argument("--slab", type=float, help="3D section: thickness of the slab of points shown [m] (default: one voxel)")
    r.set_defaults(run=cmd_render)
    rep = sub.add_parser("report", help="self-contained HTML report")
    rep.add_argument("outdir")
    rep.add_argument("-o", "--output")
    rep.add_argument("--field", help="field of the frame pictures (default: displacement)")
    rep.set_defaults(run=cmd_report)
    sw = sub.add_parser("sweep", help="picture of a sweep's sweep.csv (run by `skred sweep`)")
    sw.add_argument("outdir")
    sw.add_argument("-o", "--output", help="PNG file (default OUTDIR/pictures/sweep.png)")
    sw.add_argument("--dpi", type=int, default=100)
    sw.set_defaults(run=cmd_sweep)
    rf = sub.add_parser("refine", help="picture of a refinement study's refine.csv (run by `skred refine`)")
    rf.add_argument("outdir")
    rf.add_argument("-o", "--output", help="PNG file (default OUTDIR/pictures/refine.png)")
    rf.add_argument("--dpi", type=int, default=100)
    rf.set_defaults(run=cmd_refine)
    fo = sub.add_parser("fos", help="picture of a strength-reduction study's fos.csv (run by `skred fos`)")
    fo.add_argument("outdir")
    fo.add_argument("-o", "--output", help="PNG file (default OUTDIR/pictures/fos.png)")
    fo.add_argument("--dpi", type=int, default=100)
    fo.set_defaults(run=cmd_fos)
    return p


def main(argv):
    a = parser().parse_args(argv)
    if not os.path.isdir(a.outdir):
        print(f"skred: {a.outdir} is not a folder", file=sys.stderr)
        return 1
    try:
        return a.run(a)
    except PostError as e:
        print(f"skred: {e}", file=sys.stderr)
        return 1


def entry():
    """The `skred-post` command of the installed package: skred-post render|report|sweep|refine|fos ..."""
    from .deps import require_modules
    require_modules()
    sys.exit(main(sys.argv[1:]))
