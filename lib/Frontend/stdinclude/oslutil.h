// osl-mlir's oslutil.h: the utility functions OSL's header of that name
// declares, written here. draw_string draws with osl-mlir's own 5x7 font
// (oslutil-font.h), so its letters are not OSL's pixel for pixel.
#pragma once
#define OSLUTIL_H

#include "oslutil-font.h"

// 1 within line_width of an edge of the surface, else 0. edge_type
// "patches": the edges u = 0, u = 1, v = 0, v = 1 of the parametric patch;
// "triangles" and "polygons": the edges of the triangle the renderer names
// in the attribute "geom:trianglevertices" (0 where it names none). With
// raster != 0 line_width is in pixels (through the derivatives of u and v,
// or of P in raster space), otherwise in the units of P.
float wireframe(string edge_type, float line_width, int raster)
{
    float half_width = 0.5 * line_width;
    if (edge_type == "patches") {
        float du = min(u, 1 - u);
        float dv = min(v, 1 - v);
        if (raster) {
            du /= max(filterwidth(u), 1e-9);
            dv /= max(filterwidth(v), 1e-9);
        } else {
            du *= length(dPdu);
            dv *= length(dPdv);
        }
        return min(du, dv) <= half_width ? 1 : 0;
    }
    point corners[3];
    if (!getattribute("geom:trianglevertices", corners))
        return 0;
    point p = P;
    if (raster) {
        p = transform("raster", p);
        for (int i = 0; i < 3; ++i)
            corners[i] = transform("raster", corners[i]);
        // Distances on the image plane.
        p[2] = 0;
        for (int i = 0; i < 3; ++i)
            corners[i][2] = 0;
    }
    float nearest = 1e30;
    for (int i = 0; i < 3; ++i) {
        point a = corners[i], b = corners[(i + 1) % 3];
        vector edge = b - a;
        float along = clamp(dot(p - a, edge) / max(dot(edge, edge), 1e-30), 0, 1);
        nearest = min(nearest, distance(p, a + along * edge));
    }
    return nearest <= half_width ? 1 : 0;
}

float wireframe(string edge_type, float line_width)
{
    return wireframe(edge_type, line_width, 1);
}

float wireframe(string edge_type)
{
    return wireframe(edge_type, 1.0, 1);
}

float wireframe()
{
    return wireframe("polygons", 1.0, 1);
}

// 1 where (s, t) falls on a lit pixel of str drawn with its top-left corner
// at (0, 0), else 0. s grows to the right and t downwards, in font pixels:
// each character takes a cell 6 wide (5 and a gap) and 8 high (7 and a
// gap). wrap_s repeats the string along s, wrap_t the line along t;
// jitter moves each character up or down by one font pixel or not,
// chosen by cellnoise of its position in the string.
float draw_string(string str, float s, float t, int wrap_s, int wrap_t, int jitter)
{
    int len = strlen(str);
    if (len == 0)
        return 0;
    float x = wrap_s ? mod(s, 6.0 * len) : s;
    float y = wrap_t ? mod(t, 8.0) : t;
    if (x < 0 || x >= 6.0 * len)
        return 0;
    int index = (int) floor(x / 6);
    int column = (int) floor(x) - 6 * index;
    if (jitter)
        y += floor(3 * cellnoise(index + 0.5)) - 1;
    int row = (int) floor(y);
    if (y < 0 || column > 4 || row > 6)
        return 0;
    int c = getchar(str, index);
    if (c < 32 || c > 126)
        return 0;
    int font[665] = OSLUTIL_FONT_ROWS;
    return (font[7 * (c - 32) + row] >> (4 - column)) & 1;
}

float draw_string(string str, float s, float t)
{
    return draw_string(str, s, t, 0, 0, 0);
}
