"""The frame of reel's SVG plots (docs/images/*.svg): a white page, grid lines and their numbers at
the given ticks, and the two axis labels. `px(x, y)` maps data to pixels; returns the SVG's opening
lines, for the caller to add its curves and legend to and close with "</svg>"."""


def axes(W, H, L, B, px, xticks, yticks, xlabel, ylabel):
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (W, H),
           '<rect width="100%" height="100%" fill="white"/>']
    for t in xticks:
        x, _ = px(t, 0)
        out.append('<line x1="%.1f" y1="15" x2="%.1f" y2="%d" stroke="#ddd"/>' % (x, x, H - B))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%d</text>' % (x, H - B + 16, t))
    for v in yticks:
        _, y = px(0, v)
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (L, y, W - 15, y))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%d</text>' % (L - 6, y + 4, v))
    out.append('<text x="%d" y="%d" text-anchor="middle">%s</text>' % ((W + L) // 2, H - 6, xlabel))
    out.append('<text x="14" y="%d" transform="rotate(-90 14 %d)" text-anchor="middle">%s</text>' % (H // 2, H // 2, ylabel))
    return out
