/* gles2-probe: draws one GL ES 2.0 feature per scene into a 64x64 X11 window, so that a
 * capture of it (apitrace trace --api egl) can be replayed by tiler and by llvmpipe.
 * Build: gcc -O1 -o probe probe.c -lEGL -lGLESv2 -lX11. Run: ./probe SCENE (see main). */
#include <EGL/egl.h>
#include <GLES2/gl2.h>
#include <X11/Xlib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 64
#define H 64

static EGLDisplay dpy;
static EGLSurface surf;

static void die(const char *what) {
    fprintf(stderr, "probe: %s\n", what);
    exit(1);
}

/* The GL ES version of the context: 2, or 3 for scenes that need it (ETC2). */
static int es_version = 2;

static void setup(void) {
    Display *x = XOpenDisplay(NULL);
    if (!x) die("no X display");
    Window win = XCreateSimpleWindow(x, DefaultRootWindow(x), 0, 0, W, H, 0, 0, 0);
    XMapWindow(x, win);
    XFlush(x);
    dpy = eglGetDisplay((EGLNativeDisplayType)x);
    if (!eglInitialize(dpy, NULL, NULL)) die("eglInitialize");
    EGLint attribs[] = {EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
                        EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8, EGL_RENDERABLE_TYPE, es_version == 3 ? 0x40 /* EGL_OPENGL_ES3_BIT */ : EGL_OPENGL_ES2_BIT,
                        EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_NONE};
    EGLConfig config;
    EGLint n;
    if (!eglChooseConfig(dpy, attribs, &config, 1, &n) || n != 1) die("eglChooseConfig");
    surf = eglCreateWindowSurface(dpy, config, (EGLNativeWindowType)win, NULL);
    if (surf == EGL_NO_SURFACE) die("eglCreateWindowSurface");
    EGLint ctx_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, es_version, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attribs);
    if (ctx == EGL_NO_CONTEXT) die("eglCreateContext");
    if (!eglMakeCurrent(dpy, surf, surf, ctx)) die("eglMakeCurrent");
    glViewport(0, 0, W, H);
}

static GLuint shader(GLenum kind, const char *source) {
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, NULL);
    glCompileShader(s);
    GLint ok;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "%s\n", log);
        die("compile");
    }
    return s;
}

static GLuint program(const char *vs, const char *fs) {
    GLuint p = glCreateProgram();
    GLuint v = shader(GL_VERTEX_SHADER, vs), f = shader(GL_FRAGMENT_SHADER, fs);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glBindAttribLocation(p, 0, "position");
    glBindAttribLocation(p, 1, "uv");
    glLinkProgram(p);
    GLint ok;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) die("link");
    glDeleteShader(v);
    glDeleteShader(f);
    return p;
}

static const char *textured_vs =
    "attribute vec2 position;\nattribute vec2 uv;\nvarying vec2 v_uv;\n"
    "void main() { v_uv = uv; gl_Position = vec4(position, 0.0, 1.0); }\n";
static const char *textured_fs =
    "precision mediump float;\nvarying vec2 v_uv;\nuniform sampler2D tex;\n"
    "void main() { gl_FragColor = texture2D(tex, v_uv); }\n";
static const char *solid_vs =
    "attribute vec2 position;\nuniform float depth;\n"
    "void main() { gl_Position = vec4(position, depth, 1.0); }\n";
static const char *solid_fs =
    "precision mediump float;\nuniform vec4 color;\nvoid main() { gl_FragColor = color; }\n";

/* A quad from (x0,y0) to (x1,y1) in NDC with texture coordinates (s0,t0)-(s1,t1), drawn
 * from client memory as a triangle strip. */
static void quad(float x0, float y0, float x1, float y1, float s0, float t0, float s1, float t1) {
    float pos[] = {x0, y0, x1, y0, x0, y1, x1, y1};
    float uv[] = {s0, t0, s1, t0, s0, t1, s1, t1};
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, pos);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, uv);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

/* A w x h RGBA checker of cell x cell texels in the colours a and b. */
static GLuint checker_cells(int w, int h, int cell, const unsigned char a[4], const unsigned char b[4]) {
    unsigned char *texels = malloc(w * h * 4);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) memcpy(texels + (y * w + x) * 4, (((x / cell) ^ (y / cell)) & 1) ? a : b, 4);
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    free(texels);
    return t;
}

static GLuint checker(int w, int h, const unsigned char a[4], const unsigned char b[4]) {
    return checker_cells(w, h, 1, a, b);
}

static void params(GLenum min, GLenum mag, GLenum wrap_s, GLenum wrap_t) {
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, mag);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap_s);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap_t);
}

static const unsigned char red[4] = {255, 0, 0, 255}, blue[4] = {0, 0, 255, 255},
                           white[4] = {255, 255, 255, 255}, green[4] = {0, 200, 0, 255};

/* Separate min/mag filters and S/T wraps: four quarters, each a sampler state. */
static void scene_sampler(void) {
    GLuint p = program(textured_vs, textured_fs);
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "tex"), 0);
    glClearColor(0.1f, 0.1f, 0.1f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    checker(4, 4, red, blue);
    /* Magnified: linear mag, nearest min; S repeats, T clamps. */
    params(GL_NEAREST, GL_LINEAR, GL_REPEAT, GL_CLAMP_TO_EDGE);
    quad(-1, -1, 0, 0, -0.6f, -0.6f, 1.4f, 1.4f);
    /* Magnified: nearest mag, linear min; S mirrored, T repeats. */
    params(GL_LINEAR, GL_NEAREST, GL_MIRRORED_REPEAT, GL_REPEAT);
    quad(0, -1, 1, 0, -0.7f, -0.3f, 1.3f, 1.7f);
    /* Minified (cells of 4 texels, so that nearest sampling does not alias): nearest min,
     * linear mag; S clamps, T mirrored. */
    checker_cells(64, 64, 4, white, green);
    params(GL_NEAREST, GL_LINEAR, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT);
    quad(-1, 0, 0, 1, -0.23f, -0.47f, 1.27f, 1.41f);
    /* Minified: linear min, nearest mag. */
    params(GL_LINEAR, GL_NEAREST, GL_REPEAT, GL_MIRRORED_REPEAT);
    quad(0, 0, 1, 1, 0.0f, 0.0f, 3.0f, 2.0f);
    eglSwapBuffers(dpy, surf);
}

/* Incomplete textures sample (0, 0, 0, 1) (GL ES 2.0 section 3.8.2): four columns, a mipmap
 * filter without levels, a non-power-of-two texture that repeats, the same clamped (complete),
 * and a complete power-of-two one. */
static void scene_incomplete(void) {
    GLuint p = program(textured_vs, textured_fs);
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "tex"), 0);
    glClearColor(0.5f, 0.5f, 0.5f, 0.5f);
    glClear(GL_COLOR_BUFFER_BIT);
    checker(8, 8, red, blue);
    params(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_REPEAT, GL_REPEAT);
    quad(-1, -1, -0.5f, 1, 0, 0, 1, 1);
    checker(6, 6, white, green);
    params(GL_NEAREST, GL_NEAREST, GL_REPEAT, GL_REPEAT);
    quad(-0.5f, -1, 0, 1, 0, 0, 1, 1);
    checker(6, 6, white, green);
    params(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
    quad(0, -1, 0.5f, 1, 0, 0, 1, 1);
    checker(8, 8, red, blue);
    params(GL_LINEAR, GL_LINEAR, GL_REPEAT, GL_REPEAT);
    quad(0.5f, -1, 1, 1, 0, 0, 1, 1);
    eglSwapBuffers(dpy, surf);
}

static void solid(GLuint p, float depth, const float rgba[4]) {
    glUniform1f(glGetUniformLocation(p, "depth"), depth);
    glUniform4fv(glGetUniformLocation(p, "color"), 1, rgba);
}

/* Separate front and back stencil: a front-facing and a back-facing triangle write different
 * stencil values, then a full-window quad shows where each landed. */
static void scene_stencil(void) {
    GLuint p = program(solid_vs, solid_fs);
    glUseProgram(p);
    glClearColor(0, 0, 0, 1);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_STENCIL_TEST);
    glStencilFuncSeparate(GL_FRONT, GL_ALWAYS, 0x13, 0xff);
    glStencilFuncSeparate(GL_BACK, GL_ALWAYS, 0x2c, 0xff);
    glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_REPLACE);
    glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_INVERT);
    glStencilMaskSeparate(GL_FRONT, 0x0f);
    glStencilMaskSeparate(GL_BACK, 0xf0);
    float dark[4] = {0.2f, 0.2f, 0.2f, 1};
    solid(p, 0, dark);
    /* Counter-clockwise (front) on the left, clockwise (back) on the right, overlapping. */
    float front[] = {-1, -1, 0.3f, -1, -1, 1};
    float back[] = {1, -1, -0.3f, -1, 1, 1};
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, front);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, back);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    /* Read the values back as colours: stencil 0x03 red, 0xf0 (inverted 0 under mask f0)
     * green, 0xf3 blue; front tests with EQUAL, back never passes. */
    glStencilMask(0);
    float full[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, full);
    const struct { int ref; float rgba[4]; } shows[] = {
        {0x03, {1, 0, 0, 1}}, {0xf0, {0, 1, 0, 1}}, {0xf3, {0, 0, 1, 1}}};
    for (int i = 0; i < 3; i++) {
        glStencilFuncSeparate(GL_FRONT, GL_EQUAL, shows[i].ref, 0xff);
        glStencilFuncSeparate(GL_BACK, GL_NEVER, 0, 0xff);
        solid(p, 0, shows[i].rgba);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    }
    glDisable(GL_STENCIL_TEST);
    eglSwapBuffers(dpy, surf);
}

/* Byte indices from a buffer object, and a program deleted while in use keeps drawing. */
static void scene_indices(void) {
    GLuint p = program(solid_vs, solid_fs);
    glUseProgram(p);
    glDeleteProgram(p);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    float verts[] = {-1, -1, 1, -1, -1, 1, 1, 1, 0, 0.5f};
    unsigned char indices[] = {0, 1, 4, 2, 4, 3};
    GLuint b[2];
    glGenBuffers(2, b);
    glBindBuffer(GL_ARRAY_BUFFER, b[0]);
    glBufferData(GL_ARRAY_BUFFER, sizeof verts, verts, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof indices, indices, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, 0);
    float yellow[4] = {1, 1, 0, 1}, cyan[4] = {0, 1, 1, 1};
    solid(p, 0, yellow);
    glDrawElements(GL_TRIANGLES, 3, GL_UNSIGNED_BYTE, 0);
    solid(p, 0, cyan);
    glDrawElements(GL_TRIANGLES, 3, GL_UNSIGNED_BYTE, (const void *)3);
    glUseProgram(0);
    eglSwapBuffers(dpy, surf);
}

/* Polygon offset: a sloped quad, then the same quad pulled forward by an offset in a second
 * colour with depth test LESS: only the offset makes it win. */
static void scene_offset(void) {
    GLuint p = program(
        "attribute vec2 position;\nattribute vec2 uv;\n"
        "void main() { gl_Position = vec4(position, uv.x, 1.0); }\n",
        solid_fs);
    glUseProgram(p);
    glClearColor(0, 0, 0, 1);
    glClearDepthf(1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    float c1[4] = {1, 0.5f, 0, 1}, c2[4] = {0, 0.5f, 1, 1}, c3[4] = {1, 1, 1, 1};
    GLint color = glGetUniformLocation(p, "color");
    glUniform4fv(color, 1, c1);
    /* Depth from uv.x: a slope across x on the left half, flat on the right. */
    quad(-1, -1, 0, 1, -0.5f, 0, 0.5f, 0);
    quad(0, -1, 1, 1, 0.2f, 0, 0.2f, 0);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1, -2);
    glUniform4fv(color, 1, c2);
    quad(-1, -1, 0, 0, -0.5f, 0, 0.5f, 0);
    quad(0, -1, 1, 0, 0.2f, 0, 0.2f, 0);
    /* A positive offset pushes it behind: nothing of c3 shows in the top half. */
    glPolygonOffset(1, 1);
    glUniform4fv(color, 1, c3);
    quad(-1, 0, 0, 1, -0.5f, 0, 0.5f, 0);
    quad(0, 0, 1, 1, 0.2f, 0, 0.2f, 0);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);
    eglSwapBuffers(dpy, surf);
}

/* glCopyTexImage2D / glCopyTexSubImage2D: four coloured quarters are drawn, copied into a
 * texture (the bottom-left 32x32 pixels, then the top-right 16x16 over its corner), the window
 * cleared, and the texture drawn over the whole window. */
static void scene_copy(void) {
    GLuint p = program(solid_vs, solid_fs);
    glUseProgram(p);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    const float colors[4][4] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 0, 1}};
    const float corners[4][2] = {{-1, -1}, {0, -1}, {-1, 0}, {0, 0}};
    for (int i = 0; i < 4; i++) {
        solid(p, 0, colors[i]);
        float x = corners[i][0], y = corners[i][1];
        /* Smaller than a quarter, so the copy catches edges. */
        quad(x + 0.125f, y + 0.125f, x + 1, y + 1, 0, 0, 0, 0);
    }
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 0, 0, 32, 32, 0);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 16, 16, 40, 40, 16, 16);
    params(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
    glClearColor(0.3f, 0.3f, 0.3f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    GLuint q = program(textured_vs, textured_fs);
    glUseProgram(q);
    glUniform1i(glGetUniformLocation(q, "tex"), 0);
    quad(-1, -1, 1, 1, 0, 0, 1, 1);
    eglSwapBuffers(dpy, surf);
}

/* Lines: GL_LINES of widths 1, 3 and 6 (x-major, y-major, diagonal), a GL_LINE_STRIP and a
 * GL_LINE_LOOP, colours interpolated along them. */
static void scene_lines(void) {
    GLuint p = program(
        "attribute vec2 position;\nattribute vec2 uv;\nvarying vec2 v_uv;\n"
        "void main() { v_uv = uv; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "precision mediump float;\nvarying vec2 v_uv;\n"
        "void main() { gl_FragColor = vec4(v_uv, 1.0 - v_uv.x, 1.0); }\n");
    glUseProgram(p);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    const float widths[3] = {1, 3, 6};
    const float lines[3][4] = {{-0.9f, 0.83f, 0.87f, 0.61f}, {-0.71f, -0.9f, -0.52f, 0.53f}, {-0.3f, -0.8f, 0.6f, 0.1f}};
    for (int i = 0; i < 3; i++) {
        float uv[] = {0, 0, 1, 1};
        glLineWidth(widths[i]);
        glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, lines[i]);
        glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, uv);
        glDrawArrays(GL_LINES, 0, 2);
    }
    glLineWidth(2);
    float strip[] = {0.1f, -0.93f, 0.33f, -0.41f, 0.91f, -0.62f, 0.72f, -0.95f};
    float strip_uv[] = {0, 1, 0.3f, 0.2f, 0.7f, 0.9f, 1, 0};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, strip);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, strip_uv);
    glDrawArrays(GL_LINE_STRIP, 0, 4);
    glLineWidth(1);
    float loop[] = {0.2f, 0.21f, 0.52f, 0.27f, 0.41f, 0.47f};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, loop);
    glDrawArrays(GL_LINE_LOOP, 0, 3);
    eglSwapBuffers(dpy, surf);
}

/* Points: GL_POINTS sized by gl_PointSize, coloured by gl_PointCoord. Odd sizes sit on pixel
 * centres and even ones on pixel corners, so no square edge passes through a pixel centre. */
static void scene_points(void) {
    GLuint p = program(
        "attribute vec2 position;\nattribute vec2 uv;\n"
        "void main() { gl_PointSize = uv.x; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "precision mediump float;\n"
        "void main() { gl_FragColor = vec4(gl_PointCoord, 1.0 - gl_PointCoord.x, 1.0); }\n");
    glUseProgram(p);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    /* Pixel (x, y) centre at NDC ((x + 0.5) / 32 - 1, ...); corner at x / 32 - 1. */
    float pos[5 * 2], size[5 * 2];
    const float where[5][3] = {{10.5f, 10.5f, 1}, {30.5f, 12.5f, 5}, {50, 14, 8}, {14, 44, 16}, {44.5f, 44.5f, 21}};
    for (int i = 0; i < 5; i++) {
        pos[2 * i] = where[i][0] / 32 - 1;
        pos[2 * i + 1] = where[i][1] / 32 - 1;
        size[2 * i] = where[i][2];
        size[2 * i + 1] = 0;
    }
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, pos);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, size);
    glDrawArrays(GL_POINTS, 0, 5);
    eglSwapBuffers(dpy, surf);
}

/* Cube maps: six 32x32 faces whose texels encode the direction of their centre (colour =
 * 0.5 + 0.5 * normalised direction, so a face or orientation mix-up shows everywhere, and
 * neighbouring faces meet with nearly equal texels), an 8x8 glTexSubImage2D square inside
 * +Z, generated mip levels. Top half: a latitude/longitude panorama over all six faces
 * (minified, so levels 1-3 are read) times a 2x2 2D texture on another unit; bottom left:
 * textureCube with a bias; bottom right: colours fetched per vertex by textureCubeLod (inside the
 * faces: llvmpipe filters across face edges, tiler within a face as ES 2.0 does). */
static void cube_face_texels(int face, int size, unsigned char *out) {
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            float sc = 2.0f * (x + 0.5f) / size - 1.0f, tc = 2.0f * (y + 0.5f) / size - 1.0f, d[3];
            switch (face) { /* GL ES 2.0 table 3.21, inverted */
            case 0: d[0] = 1; d[1] = -tc; d[2] = -sc; break;
            case 1: d[0] = -1; d[1] = -tc; d[2] = sc; break;
            case 2: d[0] = sc; d[1] = 1; d[2] = tc; break;
            case 3: d[0] = sc; d[1] = -1; d[2] = -tc; break;
            case 4: d[0] = sc; d[1] = -tc; d[2] = 1; break;
            default: d[0] = -sc; d[1] = -tc; d[2] = -1; break;
            }
            float n = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            unsigned char *t = out + (y * size + x) * 4;
            for (int c = 0; c < 3; c++) t[c] = (unsigned char)(255.0f * (0.5f + 0.5f * d[c] / n) + 0.5f);
            t[3] = 255;
        }
}

static void scene_cube(void) {
    const int size = 32;
    unsigned char *texels = malloc(size * size * 4);
    GLuint t[2];
    glGenTextures(2, t);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_CUBE_MAP, t[1]);
    for (int face = 0; face < 6; face++) {
        cube_face_texels(face, size, texels);
        glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, 0, GL_RGBA, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    }
    for (int i = 0; i < 8 * 8; i++) memcpy(texels + i * 4, (const unsigned char[4]){255, 0, 255, 255}, 4);
    glTexSubImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_Z, 0, 12, 4, 8, 8, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    free(texels);
    glGenerateMipmap(GL_TEXTURE_CUBE_MAP);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    /* A 2x2 tint on unit 0. */
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t[0]);
    const unsigned char tint[16] = {255, 255, 255, 255, 200, 255, 255, 255, 255, 200, 255, 255, 255, 255, 200, 255};
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE, tint);
    params(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);

    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    GLuint p = program(textured_vs,
        "precision highp float;\nvarying vec2 v_uv;\nuniform samplerCube env;\nuniform sampler2D tint;\n"
        "uniform float bias;\nuniform vec4 view;\n"
        "void main() {\n"
        "  float lon = (v_uv.x * 2.0 - 1.0) * view.x + view.z, lat = (v_uv.y - 0.5) * view.y + view.w;\n"
        "  vec3 d = vec3(cos(lat) * sin(lon), sin(lat), cos(lat) * cos(lon));\n"
        "  gl_FragColor = textureCube(env, d, bias) * texture2D(tint, v_uv);\n"
        "}\n");
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "env"), 1);
    glUniform1i(glGetUniformLocation(p, "tint"), 0);
    glUniform1f(glGetUniformLocation(p, "bias"), 0.0f);
    glUniform4f(glGetUniformLocation(p, "view"), 3.14159265f, 2.8f, 0.0f, 0.0f);
    quad(-1, 0, 1, 1, 0, 0, 1, 1);
    /* A closer view across the +X/+Y/+Z corner, biased one level down. */
    glUniform1f(glGetUniformLocation(p, "bias"), 1.0f);
    glUniform4f(glGetUniformLocation(p, "view"), 1.2f, 1.2f, 0.785f, 0.6f);
    quad(-1, -1, 0, 0, 0, 0, 1, 1);
    GLuint q = program(
        "attribute vec2 position;\nattribute vec2 uv;\nuniform samplerCube env;\nvarying vec4 c;\n"
        "void main() {\n"
        "  c = textureCubeLod(env, vec3(uv.x * 2.0 - 1.0, 0.3, uv.y - 0.4), 3.0);\n"
        "  gl_Position = vec4(position, 0.0, 1.0);\n"
        "}\n",
        "precision mediump float;\nvarying vec4 c;\nvoid main() { gl_FragColor = c; }\n");
    glUseProgram(q);
    glUniform1i(glGetUniformLocation(q, "env"), 1);
    quad(0, -1, 1, 0, 0, 0, 1, 1);
    eglSwapBuffers(dpy, surf);
}

/* Compressed textures with mip chains given level by level (glCompressedTexImage2D), GL ES 3:
 * the left half an ETC2 RGBA8 texture, the right half ASTC 8x8 (when the driver exposes
 * KHR_texture_compression_astc_ldr; else the right half stays the clear colour). Both are
 * 64x128 on 32x64 pixels with NEAREST_MIPMAP_NEAREST: level 1, texel for pixel. Every block
 * is one flat colour, so any conforming decoder gives the same texels: ETC2 blocks in
 * individual mode with all modifiers +2 (colour c*17+2) and EAC alpha of multiplier 0, ASTC
 * void-extent blocks (UNORM16 v*257). */
#define GL_COMPRESSED_RGBA8_ETC2_EAC 0x9278
#define GL_COMPRESSED_RGBA_ASTC_8x8_KHR 0x93B7
static void scene_compressed(void) {
    const char *extensions = (const char *)glGetString(GL_EXTENSIONS);
    int astc = strstr(extensions, "GL_KHR_texture_compression_astc_ldr") != NULL;
    fprintf(stderr, "probe: ASTC LDR %s\n", astc ? "exposed" : "not exposed");
    GLuint p = program(textured_vs, textured_fs);
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "tex"), 0);
    glClearColor(0.2f, 0.2f, 0.2f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    static unsigned char blocks[64 * 128];
    GLuint t[2];
    glGenTextures(2, t);
    glBindTexture(GL_TEXTURE_2D, t[0]);
    for (int level = 0, w = 64, h = 128;; level++, w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1) {
        int bw = (w + 3) / 4, bh = (h + 3) / 4;
        for (int by = 0; by < bh; by++)
            for (int bx = 0; bx < bw; bx++) {
                unsigned char *b = blocks + (by * bw + bx) * 16;
                memset(b, 0, 16);
                b[0] = 255 - 20 * level;
                int r = bx % 15, g = by % 15, bl = (2 * level + 3) % 15;
                b[8] = r << 4 | r;
                b[9] = g << 4 | g;
                b[10] = bl << 4 | bl;
            }
        glCompressedTexImage2D(GL_TEXTURE_2D, level, GL_COMPRESSED_RGBA8_ETC2_EAC, w, h, 0, bw * bh * 16, blocks);
        if (w == 1 && h == 1) break;
    }
    params(GL_NEAREST_MIPMAP_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
    quad(-1, -1, 0, 1, 0, 0, 1, 1);
    if (astc) {
        glBindTexture(GL_TEXTURE_2D, t[1]);
        for (int level = 0, w = 64, h = 128;; level++, w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1) {
            int bw = (w + 7) / 8, bh = (h + 7) / 8;
            for (int by = 0; by < bh; by++)
                for (int bx = 0; bx < bw; bx++) {
                    unsigned char *b = blocks + (by * bw + bx) * 16;
                    static const unsigned char head[8] = {0xfc, 0xfd, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
                    memcpy(b, head, 8);
                    unsigned char rgba[4] = {(unsigned char)(40 * bx + 30), (unsigned char)(25 * by + 10),
                                             (unsigned char)(200 - 20 * level), 255};
                    for (int c = 0; c < 4; c++) b[8 + 2 * c] = b[9 + 2 * c] = rgba[c];
                }
            glCompressedTexImage2D(GL_TEXTURE_2D, level, GL_COMPRESSED_RGBA_ASTC_8x8_KHR, w, h, 0, bw * bh * 16, blocks);
            if (w == 1 && h == 1) break;
        }
        params(GL_NEAREST_MIPMAP_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
        quad(0, -1, 1, 1, 0, 0, 1, 1);
    }
    eglSwapBuffers(dpy, surf);
}

int main(int argc, char **argv) {
    const struct { const char *name; void (*draw)(void); } scenes[] = {
        {"sampler", scene_sampler}, {"incomplete", scene_incomplete}, {"stencil", scene_stencil},
        {"indices", scene_indices}, {"offset", scene_offset}, {"copy", scene_copy}, {"lines", scene_lines}, {"points", scene_points},
        {"cube", scene_cube},
        {"compressed", scene_compressed}};
    if (argc != 2) die("usage: probe SCENE");
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        if (strcmp(argv[1], scenes[i].name) == 0) {
            if (scenes[i].draw == scene_compressed) es_version = 3;
            setup();
            scenes[i].draw();
            return 0;
        }
    }
    die("unknown scene");
}
