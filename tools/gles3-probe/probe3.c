/* gles3-probe: draws one GL ES 3.0 feature per scene into a 64x64 X11 window from an ES 3
 * context, so that a capture of it (apitrace trace --api egl) can be replayed by tiler and by
 * llvmpipe. Build: gcc -O1 -o probe3 probe3.c -lEGL -lGLESv2 -lX11. Run: ./probe3 SCENE. */
#include <EGL/egl.h>
#include <GLES3/gl3.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 64
#define H 64

static EGLDisplay dpy;
static EGLSurface surf;

static void die(const char *what) {
    fprintf(stderr, "probe3: %s\n", what);
    exit(1);
}

static void setup(void) {
    Display *x = XOpenDisplay(NULL);
    if (!x) die("no X display");
    Window win = XCreateSimpleWindow(x, DefaultRootWindow(x), 0, 0, W, H, 0, 0, 0);
    XMapWindow(x, win);
    XFlush(x);
    dpy = eglGetDisplay((EGLNativeDisplayType)x);
    if (!eglInitialize(dpy, NULL, NULL)) die("eglInitialize");
    EGLint attribs[] = {EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
                        EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                        EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_NONE};
    EGLConfig config;
    EGLint n;
    if (!eglChooseConfig(dpy, attribs, &config, 1, &n) || n != 1) die("eglChooseConfig");
    surf = eglCreateWindowSurface(dpy, config, (EGLNativeWindowType)win, NULL);
    if (surf == EGL_NO_SURFACE) die("eglCreateWindowSurface");
    EGLint ctx_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, 3, EGL_NONE};
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

/* A program; attributes "position" at 0 and "color" at 1 unless the shader places them. */
static GLuint program(const char *vs, const char *fs) {
    GLuint p = glCreateProgram();
    GLuint v = shader(GL_VERTEX_SHADER, vs), f = shader(GL_FRAGMENT_SHADER, fs);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glBindAttribLocation(p, 0, "position");
    glBindAttribLocation(p, 1, "color");
    glLinkProgram(p);
    GLint ok;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        fprintf(stderr, "%s\n", log);
        die("link");
    }
    glDeleteShader(v);
    glDeleteShader(f);
    return p;
}

static GLuint buffer(GLenum target, GLsizeiptr size, const void *data) {
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, size, data, GL_STATIC_DRAW);
    return b;
}

static const char *color_vs =
    "attribute vec2 position;\nattribute vec4 color;\nvarying vec4 v_color;\n"
    "void main() { v_color = color; gl_Position = vec4(position, 0.0, 1.0); }\n";
static const char *color_fs =
    "precision mediump float;\nvarying vec4 v_color;\nvoid main() { gl_FragColor = v_color; }\n";

/* Vertex array objects: two arrays set up once (interleaved position + colour in one
 * buffer and indices; separate buffers with unsigned-byte colours), drawn alternately;
 * the default array with client-side arrays in between keeps its own state. */
static void scene_vao(void) {
    GLuint p = program(color_vs, color_fs);
    glUseProgram(p);
    GLuint vao[2];
    glGenVertexArrays(2, vao);

    const float quad[] = {-0.9f, -0.9f, 1, 0, 0, 1, -0.1f, -0.9f, 0, 1, 0, 1,
                          -0.9f, -0.1f, 0, 0, 1, 1, -0.1f, -0.1f, 1, 1, 0, 1};
    const GLushort quad_indices[] = {0, 1, 2, 2, 1, 3};
    glBindVertexArray(vao[0]);
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    buffer(GL_ELEMENT_ARRAY_BUFFER, sizeof quad_indices, quad_indices);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(2 * sizeof(float)));

    const float tri[] = {0.1f, 0.1f, 0.9f, 0.1f, 0.5f, 0.9f};
    const GLubyte tri_colors[] = {255, 128, 0, 255, 0, 255, 128, 255, 128, 0, 255, 255};
    glBindVertexArray(vao[1]);
    buffer(GL_ARRAY_BUFFER, sizeof tri, tri);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    buffer(GL_ARRAY_BUFFER, sizeof tri_colors, tri_colors);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, (void *)0);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    glClearColor(0.2f, 0.2f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindVertexArray(vao[0]);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, (void *)0);
    /* The default array: client memory, a constant colour from a disabled attribute. */
    glBindVertexArray(0);
    const float strip[] = {0.1f, -0.9f, 0.9f, -0.9f, 0.1f, -0.1f, 0.9f, -0.1f};
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, strip);
    glDisableVertexAttribArray(1);
    glVertexAttrib4f(1, 0.9f, 0.9f, 0.2f, 1);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(vao[1]);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    /* Array 0 again: attribute 0 is still the client array, attribute 1 still disabled. */
    glBindVertexArray(0);
    const float small[] = {-0.9f, 0.1f, -0.1f, 0.1f, -0.5f, 0.9f};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, small);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDeleteVertexArrays(2, vao);
    eglSwapBuffers(dpy, surf);
}

/* Instancing: a quad drawn 12 times with per-instance offsets (divisor 1) and colours
 * (divisor 2), gl_InstanceID scaling each; then indexed instances through
 * glDrawElementsInstanced. */
static void scene_instanced(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "layout(location = 1) in vec4 color;\n"
        "layout(location = 2) in vec2 offset;\n"
        "out vec4 v_color;\n"
        "void main() {\n"
        "  float s = 1.0 - float(gl_InstanceID) * 0.05;\n"
        "  v_color = color;\n"
        "  gl_Position = vec4(position * s + offset, 0.0, 1.0);\n"
        "}\n",
        "#version 300 es\nprecision mediump float;\nin vec4 v_color;\nout vec4 frag;\n"
        "void main() { frag = v_color; }\n");
    glUseProgram(p);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-0.1f, -0.1f, 0.1f, -0.1f, -0.1f, 0.1f, 0.1f, 0.1f};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    float offsets[12 * 2];
    for (int i = 0; i < 12; i++) {
        offsets[2 * i] = -0.75f + (i % 4) * 0.5f;
        offsets[2 * i + 1] = -0.75f + (i / 4) * 0.5f;
    }
    buffer(GL_ARRAY_BUFFER, sizeof offsets, offsets);
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glVertexAttribDivisor(2, 1);
    const GLubyte colors[] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255,
                              255, 255, 0, 255, 0, 255, 255, 255, 255, 0, 255, 255};
    buffer(GL_ARRAY_BUFFER, sizeof colors, colors);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, (void *)0);
    glVertexAttribDivisor(1, 2);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, 12);
    /* Indexed: the top row again, smaller, from the fourth offset on. */
    const GLushort indices[] = {0, 1, 2, 2, 1, 3};
    buffer(GL_ELEMENT_ARRAY_BUFFER, sizeof indices, indices);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    const float top[] = {-0.75f, 0.85f, -0.25f, 0.85f, 0.25f, 0.85f, 0.75f, 0.85f};
    GLuint top_buffer = buffer(GL_ARRAY_BUFFER, sizeof top, top);
    glBindBuffer(GL_ARRAY_BUFFER, top_buffer);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glVertexAttribDivisor(1, 1);
    glDrawElementsInstanced(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, (void *)0, 4);
    eglSwapBuffers(dpy, surf);
}

/* Uniform blocks: a std140 block read by the vertex shader (a matrix, a float and a vec2,
 * bound at 2 by range from an offset into a bigger buffer) and one with an instance name
 * read by the fragment shader (an array of vec4 and an int, bound at 5 by base); the
 * buffers change between draws. */
static void scene_ubo(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "layout(std140) uniform Transform {\n"
        "  mat4 m;\n"
        "  float scale;\n"
        "  vec2 shift;\n"
        "};\n"
        "void main() { gl_Position = m * vec4(position * scale + shift, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "uniform Palette {\n"
        "  vec4 colors[3];\n"
        "  int pick;\n"
        "} palette;\n"
        "out vec4 color;\n"
        "void main() { color = palette.colors[palette.pick] * 0.5 + palette.colors[0] * 0.5; }\n");
    glUseProgram(p);
    GLuint transform_index = glGetUniformBlockIndex(p, "Transform");
    GLuint palette_index = glGetUniformBlockIndex(p, "Palette");
    glUniformBlockBinding(p, transform_index, 2);
    glUniformBlockBinding(p, palette_index, 5);

    /* Transform at byte 256 of a 512-byte buffer: m (64), scale at 64, shift at 72. */
    float transform[128] = {0};
    float *t = transform + 64;
    t[0] = 1; t[5] = -1; t[10] = 1; t[15] = 1; /* flip y */
    t[16] = 0.5f;
    t[18] = -0.4f; t[19] = 0.3f;
    GLuint tb = buffer(GL_UNIFORM_BUFFER, sizeof transform, transform);
    glBindBufferRange(GL_UNIFORM_BUFFER, 2, tb, 256, 80);
    /* Palette: colors[3] at 0, 16, 32; pick at 48. */
    float palette[16] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 0};
    int pick = 2;
    memcpy(&palette[12], &pick, 4);
    GLuint pb = buffer(GL_UNIFORM_BUFFER, sizeof palette, palette);
    glBindBufferBase(GL_UNIFORM_BUFFER, 5, pb);

    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glClearColor(0.1f, 0.1f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    /* Change both blocks' data and draw again elsewhere. */
    const float shift[2] = {0.45f, -0.35f};
    glBindBuffer(GL_UNIFORM_BUFFER, tb);
    glBufferSubData(GL_UNIFORM_BUFFER, 256 + 72, sizeof shift, shift);
    const float scale = 0.3f;
    glBufferSubData(GL_UNIFORM_BUFFER, 256 + 64, sizeof scale, &scale);
    pick = 1;
    glBindBuffer(GL_UNIFORM_BUFFER, pb);
    glBufferSubData(GL_UNIFORM_BUFFER, 48, 4, &pick);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* GLSL ES 3.00: positions from gl_VertexID (no attributes), texture() and textureLod() on
 * a mip-mapped texture, outputs at a layout location. */
static void scene_glsl3(void) {
    GLuint p = program(
        "#version 300 es\n"
        "out vec2 uv;\n"
        "void main() {\n"
        "  float id = float(gl_VertexID);\n"
        "  vec2 corner = vec2(mod(id, 2.0), floor(id / 2.0));\n"
        "  uv = corner * 1.5;\n"
        "  gl_Position = vec4(corner * 1.8 - 0.9, 0.0, 1.0);\n"
        "}\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D tex;\n"
        "layout(location = 0) out vec4 color;\n"
        "void main() {\n"
        "  vec4 a = texture(tex, uv);\n"
        "  vec4 b = textureLod(tex, uv, 2.0);\n"
        "  color = uv.x < 0.75 ? a : b;\n"
        "}\n");
    glUseProgram(p);
    unsigned char texels[16 * 16 * 4];
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            unsigned char *c = texels + (y * 16 + x) * 4;
            int on = ((x / 2) ^ (y / 2)) & 1;
            c[0] = on ? 250 : 20;
            c[1] = (unsigned char)(x * 16);
            c[2] = (unsigned char)(y * 16);
            c[3] = 255;
        }
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* Immutable storage, sampler objects, buffer copies: an 8x8 texture with 4 levels from
 * glTexStorage2D, each level a colour given by glTexSubImage2D; its own parameters say
 * linear, clamped; a sampler object bound to unit 0 says nearest-mipmap-nearest, repeated,
 * for the left quad and is unbound for the right one. The quads' vertices reach their buffer
 * through glCopyBufferSubData from a staging buffer. */
static void scene_objects(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec4 vertex;\n"
        "out vec2 uv;\n"
        "void main() { uv = vertex.zw; gl_Position = vec4(vertex.xy, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D tex;\n"
        "out vec4 color;\n"
        "void main() { color = texture(tex, uv); }\n");
    glUseProgram(p);
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 4, GL_RGBA8, 8, 8);
    const unsigned char level_colors[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 0, 255}};
    unsigned char texels[8 * 8 * 4];
    for (int level = 0; level < 4; level++) {
        int size = 8 >> level;
        for (int i = 0; i < size * size; i++) {
            memcpy(texels + i * 4, level_colors[level], 4);
            if (level == 0 && ((i % 8) / 2 + i / 16) % 2) texels[i * 4 + 2] = 200; /* a checker on level 0 */
        }
        glTexSubImage2D(GL_TEXTURE_2D, level, 0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    GLuint sampler;
    glGenSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_MIRRORED_REPEAT);

    /* Two strips: x, y, s, t; the left one minifies (uv to 6), the right one magnifies. */
    const float strips[] = {-0.95f, -0.9f, 0, 0, -0.05f, -0.9f, 6, 0, -0.95f, 0.9f, 0, 6, -0.05f, 0.9f, 6, 6,
                            0.05f, -0.9f, -0.2f, -0.2f, 0.95f, -0.9f, 1.2f, -0.2f, 0.05f, 0.9f, -0.2f, 1.2f,
                            0.95f, 0.9f, 1.2f, 1.2f};
    GLuint staging = buffer(GL_COPY_READ_BUFFER, sizeof strips, strips);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    GLuint vertices = buffer(GL_ARRAY_BUFFER, sizeof strips + 64, NULL);
    glBindBuffer(GL_COPY_WRITE_BUFFER, vertices);
    glBindBuffer(GL_COPY_READ_BUFFER, staging);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 64, sizeof strips);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, (void *)64);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindSampler(0, sampler);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindSampler(0, 0);
    glDrawArrays(GL_TRIANGLE_STRIP, 4, 4);
    glDeleteSamplers(1, &sampler);
    eglSwapBuffers(dpy, surf);
}

/* Multiple render targets: one draw writes two outputs into two colour textures of a
 * framebuffer (glDrawBuffers), then the window shows the first on the left and the second
 * on the right. */
static void scene_mrt(void) {
    GLuint write = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "out vec2 p;\n"
        "void main() { p = position; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 p;\n"
        "layout(location = 0) out vec4 first;\n"
        "layout(location = 1) out vec4 second;\n"
        "void main() {\n"
        "  first = vec4(p * 0.5 + 0.5, 0.2, 1.0);\n"
        "  second = vec4(0.9, 0.5 - p.x * 0.5, p.y * p.y, 1.0);\n"
        "}\n");
    GLuint show = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "out vec2 uv;\n"
        "void main() { uv = position * 0.5 + 0.5; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D first;\n"
        "uniform sampler2D second;\n"
        "out vec4 color;\n"
        "void main() { color = uv.x < 0.5 ? texture(first, uv) : texture(second, uv); }\n");
    GLuint tex[2];
    glGenTextures(2, tex);
    for (int i = 0; i < 2; i++) {
        glActiveTexture(GL_TEXTURE0 + i);
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, W, H, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, tex[1], 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("framebuffer");
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glViewport(0, 0, W, H);
    glUseProgram(write);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glUseProgram(show);
    glUniform1i(glGetUniformLocation(show, "first"), 0);
    glUniform1i(glGetUniformLocation(show, "second"), 1);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

int main(int argc, char **argv) {
    const struct { const char *name; void (*draw)(void); } scenes[] = {
        {"vao", scene_vao}, {"instanced", scene_instanced}, {"ubo", scene_ubo}, {"glsl3", scene_glsl3},
        {"objects", scene_objects}, {"mrt", scene_mrt}};
    if (argc != 2) die("usage: probe3 SCENE");
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        if (strcmp(argv[1], scenes[i].name) == 0) {
            setup();
            scenes[i].draw();
            return 0;
        }
    }
    die("unknown scene");
}
