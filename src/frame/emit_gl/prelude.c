/* A scene uses the helpers it needs; the others stay unused. */
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-variable"
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef SCENE_GLUT
#include <GL/glut.h>
#else
#include <GL/osmesa.h>
#endif
#include <GL/gl.h>
#include <GL/glext.h>

/* ---------------------------------------------------------------------------------
 * Helpers (the same for every scene). The passes below only call these.
 * ------------------------------------------------------------------------------- */

static void die(const char *what)
{
    fprintf(stderr, "scene: %s\n", what);
    exit(1);
}

/* Seconds on the monotonic clock (CLOCK_MONOTONIC). */
static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* Seconds spent reading data files: the passes read their vertices, and main's
 * draw time leaves this out. */
static double io_seconds = 0.0;

/* A data file beside this program, exactly `bytes` long. */
static void *load_file(const char *name, size_t bytes)
{
    double t0 = now_seconds();
    FILE *f = fopen(name, "rb");
    void *p;
    if (!f) {
        fprintf(stderr, "scene: cannot open %s (run the program in its directory)\n", name);
        exit(1);
    }
    p = malloc(bytes ? bytes : 1);
    if (!p || fread(p, 1, bytes, f) != bytes) {
        fprintf(stderr, "scene: %s is not %lu bytes\n", name, (unsigned long)bytes);
        exit(1);
    }
    fclose(f);
    io_seconds += now_seconds() - t0;
    return p;
}

/* float32 data files are little-endian; so is every machine this runs on in CI. */
static const float *load_floats(const char *name, size_t count)
{
    return (const float *)load_file(name, count * sizeof(float));
}

static int has_extension(const char *name)
{
    const char *all = (const char *)glGetString(GL_EXTENSIONS);
    size_t n = strlen(name);
    while (all && (all = strstr(all, name)) != NULL) {
        if (all[n] == ' ' || all[n] == '\0')
            return 1;
        all += n;
    }
    return 0;
}

/* The extensions the scene draws with (a NULL-terminated list) and its texture units. */
static void require_gl(const char *const *ext, int units_needed)
{
    GLint units = 0;
    for (; *ext; ext++)
        if (!has_extension(*ext)) {
            fprintf(stderr, "scene: the GL context lacks %s\n", *ext);
            exit(1);
        }
    glGetIntegerv(GL_MAX_TEXTURE_UNITS, &units);
    if (units < units_needed) {
        fprintf(stderr, "scene: %d texture units needed, the context has %d\n", units_needed,
                units);
        exit(1);
    }
}

/* The bound texture's filter (min and mag) and its s and t wrap. */
static void filter_and_wrap(GLenum target, GLenum filter, GLenum wrap)
{
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, wrap);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, wrap);
}

/* An 8-bit texture (a table, a light map: GL_LUMINANCE; a colour texture: GL_RGBA) from
 * a raw file: `filter` GL_LINEAR (bilinear, as the model's samplers) or GL_NEAREST;
 * `wrap` GL_CLAMP_TO_EDGE, GL_CLAMP_TO_BORDER (border colour 0) or GL_REPEAT. */
static GLuint texture_from_file(GLenum target, const char *file, int w, int h, GLenum format,
                                GLenum filter, GLenum wrap)
{
    static const GLfloat black[4] = {0, 0, 0, 0};
    GLuint t;
    size_t bytes = (size_t)w * (size_t)h * (format == GL_RGBA ? 4 : 1);
    GLenum internal = format == GL_RGBA ? GL_RGBA8 : GL_LUMINANCE8;
    unsigned char *texels = load_file(file, bytes);
    glGenTextures(1, &t);
    glBindTexture(target, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (target == GL_TEXTURE_1D)
        glTexImage1D(target, 0, internal, w, 0, format, GL_UNSIGNED_BYTE, texels);
    else
        glTexImage2D(target, 0, internal, w, h, 0, format, GL_UNSIGNED_BYTE, texels);
    filter_and_wrap(target, filter, wrap);
    glTexParameterfv(target, GL_TEXTURE_BORDER_COLOR, black);
    free(texels);
    return t;
}

/* The "in front of the light" step: a 1D texture {0, 255}, nearest. Its coordinate is
 * 0.5 + Q_STEP * q, so a fragment behind the projector (q <= 0) reads 0 — the model
 * sets H*I_l = 0 there. */
#define Q_STEP 65536.0f
static GLuint step_texture(void)
{
    static const unsigned char texels[2] = {0, 255};
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_1D, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage1D(GL_TEXTURE_1D, 0, GL_LUMINANCE8, 2, 0, GL_LUMINANCE, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    return t;
}

/* A shadow map: a depth texture compared with ARB_shadow (lit where r <= stored),
 * nearest (the model tests one texel), read as luminance 0 or 1. */
static GLuint shadow_texture(int res)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24_ARB, res, res, 0, GL_DEPTH_COMPONENT,
                 GL_UNSIGNED_INT, NULL);
    filter_and_wrap(GL_TEXTURE_2D, GL_NEAREST, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE_ARB, GL_COMPARE_R_TO_TEXTURE_ARB);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC_ARB, GL_LEQUAL);
    glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_TEXTURE_MODE_ARB, GL_LUMINANCE);
    return t;
}

/* A screen texture (the J texture, the stage register): a region of the buffer copied
 * by glCopyTexSubImage2D, read at pixel centres (nearest). Power-of-two sides (GL 1.3);
 * the image sits in its lower-left corner. */
static GLuint screen_texture(int w, int h, GLenum format)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, format == GL_RGB ? GL_RGB8 : GL_LUMINANCE8, w, h, 0, format,
                 GL_UNSIGNED_BYTE, NULL);
    filter_and_wrap(GL_TEXTURE_2D, GL_NEAREST, GL_CLAMP_TO_EDGE);
    return t;
}

/* Draw into the w x h region at (x0, y0) of the GL buffer, in the model's own window
 * coordinates: x right and y down in pixels (row y of the model is row y of the
 * buffer, so the picture is read back without a flip), z the window depth in
 * [0, 1]. Vertices come from the host already projected, as the model's host hands
 * them to its interpolator (which interpolates linearly on the screen: w = 1 here). */
static void region(int x0, int y0, int w, int h)
{
    GLdouble m[16] = {0};
    m[0] = 2.0 / w;
    m[5] = 2.0 / h;
    m[10] = 2.0;
    m[12] = -1.0;
    m[13] = -1.0;
    m[14] = -1.0;
    m[15] = 1.0;
    glViewport(x0, y0, w, h);
    glScissor(x0, y0, w, h);
    glEnable(GL_SCISSOR_TEST);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(m);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glDepthRange(0.0, 1.0);
}

/* Texture unit `unit`: texture `tex` on `target` enabled, its colour `function`
 * (ARB_texture_env_combine: GL_REPLACE, GL_MODULATE, GL_DOT3_RGB_ARB) of arg0 and arg1
 * (GL_TEXTURE, GL_PREVIOUS, GL_PRIMARY_COLOR or GL_CONSTANT; arg1 unused by REPLACE),
 * the alpha the primary colour's. */
static void unit_combine(int unit, GLenum target, GLuint tex, GLenum function, GLenum arg0,
                         GLenum arg1)
{
    glActiveTexture(GL_TEXTURE0 + unit);
    glEnable(target);
    glBindTexture(target, tex);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE_ARB);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB_ARB, function);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_RGB_ARB, arg0);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB_ARB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE1_RGB_ARB, arg1);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB_ARB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA_ARB, GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_ALPHA_ARB, GL_PRIMARY_COLOR);
}

/* Texture unit `unit`: the product arg0 * arg1 — one 8-bit modulate, as one of the
 * model's; `constant` the GL_CONSTANT colour when not NULL. */
static void unit_modulate(int unit, GLenum target, GLuint tex, GLenum arg0, GLenum arg1,
                          const GLfloat *constant)
{
    unit_combine(unit, target, tex, GL_MODULATE, arg0, arg1);
    if (constant)
        glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, constant);
}

/* Texture unit `unit`: texture `tex` on `target` enabled, its colour passed on as is. */
static void unit_replace(int unit, GLenum target, GLuint tex)
{
    unit_combine(unit, target, tex, GL_REPLACE, GL_TEXTURE, GL_PREVIOUS_ARB);
}

/* Texture unit `unit`: the clamped dot product 4 * sum((arg0 - 1/2) * (arg1 - 1/2)) of
 * its texel and the previous stage's colour, into r, g and b (DOT3_RGB,
 * ARB_texture_env_dot3): the model's DOT3 stage. */
static void unit_dot3(int unit, GLenum target, GLuint tex)
{
    unit_combine(unit, target, tex, GL_DOT3_RGB_ARB, GL_TEXTURE, GL_PREVIOUS_ARB);
}

/* A cube map of 8-bit RGB faces from a raw file: face f (GL's order +x, -x, +y, -y,
 * +z, -z) at byte f * side * side * 3, rows of t, texels of s; clamped to each face's
 * edge (no filtering across faces, as OpenGL 1.3 and the model's address unit);
 * `filter` GL_LINEAR or GL_NEAREST. */
static GLuint cube_texture_from_file(const char *file, int side, GLenum filter)
{
    GLuint t;
    int f;
    size_t face_bytes = (size_t)side * (size_t)side * 3;
    unsigned char *texels = load_file(file, 6 * face_bytes);
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_CUBE_MAP, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (f = 0; f < 6; f++)
        glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGB8, side, side, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, texels + (size_t)f * face_bytes);
    filter_and_wrap(GL_TEXTURE_CUBE_MAP, filter, GL_CLAMP_TO_EDGE);
    free(texels);
    return t;
}

/* Every texture unit off, texture matrices and RGB scales reset. */
static void units_off(void)
{
    int u;
    for (u = 0; u < 8; u++) {
        glActiveTexture(GL_TEXTURE0 + u);
        glDisable(GL_TEXTURE_1D);
        glDisable(GL_TEXTURE_2D);
        glDisable(GL_TEXTURE_CUBE_MAP);
        glTexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE_ARB, 1.0f);
        glMatrixMode(GL_TEXTURE);
        glLoadIdentity();
        glMatrixMode(GL_MODELVIEW);
    }
    glActiveTexture(GL_TEXTURE0);
}

/* Additive blending into the framebuffer (the model's additive_blend: saturating). */
static void additive(int on)
{
    if (on) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
    } else {
        glDisable(GL_BLEND);
    }
}

/* Begin a draw into the stage region, rows h .. 2h of the buffer (cleared, no blend). */
static void stage_region(int w, int h)
{
    region(0, h, w, h);
    additive(0);
    glClear(GL_COLOR_BUFFER_BIT);
}

/* Copy the stage region into the stage texture `tex`: the 8-bit register between two of
 * the model's stages. */
static void stage_copy(GLuint tex, int w, int h)
{
    units_off();
    glBindTexture(GL_TEXTURE_2D, tex);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, h, w, h);
}

/* --- PNG: stored (uncompressed) deflate blocks, CRC-32 and Adler-32 by hand. --- */
static unsigned long crc_table[256];
static void crc_init(void)
{
    unsigned long c;
    int n, k;
    for (n = 0; n < 256; n++) {
        c = (unsigned long)n;
        for (k = 0; k < 8; k++)
            c = (c & 1) ? 0xedb88320UL ^ (c >> 1) : c >> 1;
        crc_table[n] = c;
    }
}
static unsigned long crc_update(unsigned long crc, const unsigned char *b, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        crc = crc_table[(crc ^ b[i]) & 0xff] ^ (crc >> 8);
    return crc;
}
static void put_u32(unsigned char *p, unsigned long v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}
static void png_chunk(FILE *f, const char *type, const unsigned char *data, size_t n)
{
    unsigned char len[4], crc[4];
    unsigned long c;
    put_u32(len, (unsigned long)n);
    fwrite(len, 1, 4, f);
    fwrite(type, 1, 4, f);
    if (n)
        fwrite(data, 1, n, f);
    c = crc_update(0xffffffffUL, (const unsigned char *)type, 4);
    c = crc_update(c, data, n) ^ 0xffffffffUL;
    put_u32(crc, c);
    fwrite(crc, 1, 4, f);
}
/* An 8-bit RGB PNG of w x h pixels, rows top to bottom. */
static void write_png(const char *path, int w, int h, const unsigned char *rgb)
{
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    size_t row = (size_t)w * 3 + 1, raw_n = row * (size_t)h, blocks, z_n, i, o = 0, at = 0;
    unsigned char ihdr[13], *raw, *z;
    unsigned long a = 1, b = 0;
    FILE *f = fopen(path, "wb");
    if (!f)
        die("cannot write the PNG");
    crc_init();
    raw = malloc(raw_n);
    for (i = 0; i < (size_t)h; i++) {
        raw[i * row] = 0; /* filter: none */
        memcpy(raw + i * row + 1, rgb + i * (size_t)w * 3, (size_t)w * 3);
    }
    blocks = (raw_n + 65534) / 65535;
    z_n = 2 + raw_n + 5 * (blocks ? blocks : 1) + 4;
    z = malloc(z_n);
    z[o++] = 0x78;
    z[o++] = 0x01;
    do {
        size_t n = raw_n - at > 65535 ? 65535 : raw_n - at;
        z[o++] = (unsigned char)(at + n == raw_n);
        z[o++] = (unsigned char)(n & 0xff);
        z[o++] = (unsigned char)(n >> 8);
        z[o++] = (unsigned char)(~n & 0xff);
        z[o++] = (unsigned char)((~n >> 8) & 0xff);
        memcpy(z + o, raw + at, n);
        o += n;
        at += n;
    } while (at < raw_n);
    for (i = 0; i < raw_n; i++) {
        a = (a + raw[i]) % 65521;
        b = (b + a) % 65521;
    }
    put_u32(z + o, (b << 16) | a);
    o += 4;
    put_u32(ihdr, (unsigned long)w);
    put_u32(ihdr + 4, (unsigned long)h);
    ihdr[8] = 8;  /* bits per channel */
    ihdr[9] = 2;  /* RGB */
    ihdr[10] = 0; /* deflate */
    ihdr[11] = 0; /* adaptive filters */
    ihdr[12] = 0; /* no interlace */
    fwrite(sig, 1, 8, f);
    png_chunk(f, "IHDR", ihdr, 13);
    png_chunk(f, "IDAT", z, o);
    png_chunk(f, "IEND", NULL, 0);
    fclose(f);
    free(raw);
    free(z);
}
