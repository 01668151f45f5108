/* Terrain draws in compiled code (issue 29): the per-run random rows of walker.analysis.mfpt's Monte
 * Carlo, the same numbers as numpy draws them, drawn inside the compiled batch so that a run
 * costs no Python work (see wk_terrain.h, wk_terrain_draws).
 *
 * walker.analysis.mfpt draws run i's rows with numpy.random.default_rng(child_i).standard_normal((n,
 * 2)), child_i the i-th child of numpy.random.SeedSequence(seed).spawn(runs).  Here the same
 * three steps, written from numpy's documented algorithms:
 *
 * - the child's seed sequence (entropy the seed's 32-bit words, spawn key (i,), pool of 4
 *   words): its pool by the seed sequence's hash mixing, then generate_state(4, uint64);
 * - the PCG64 generator (O'Neill's permuted congruential generator, 128-bit state, XSL-RR
 *   output) seeded as numpy's PCG64 seeds itself from those four words;
 * - the standard normals: numpy's own ziggurat (random_standard_normal, exported by
 *   numpy.random._generator; walker/simulation/_terrain_run.py looks its address up and passes it),
 *   called with a bit generator of numpy's layout (numpy/random/bitgen.h) around that PCG64.
 *
 * tests/test_terrain_draw.py checks the rows against numpy's, bit for bit.  Without 128-bit
 * integers (__SIZEOF_INT128__) nothing is drawn here (wk_terrain_draws_supported 0) and
 * walker draws in Python as before. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "wk_terrain.h"

int wk_terrain_draws_supported(void)
{
#ifdef __SIZEOF_INT128__
    return 1;
#else
    return 0;
#endif
}

#ifdef __SIZEOF_INT128__

/* ------------------------------------------------------------------------------------------
 * The seed sequence
 * ------------------------------------------------------------------------------------------ */

#define POOL 4
#define INIT_A 0x43b0d7e5u
#define MULT_A 0x931e8875u
#define INIT_B 0x8b51f9ddu
#define MULT_B 0x58f38dedu
#define MIX_MULT_L 0xca01f9ddu
#define MIX_MULT_R 0x4973f715u
#define XSHIFT 16

static uint32_t hashmix(uint32_t value, uint32_t *hash_const)
{
    value ^= *hash_const;
    *hash_const *= MULT_A;
    value *= *hash_const;
    value ^= value >> XSHIFT;
    return value;
}

static uint32_t mix(uint32_t x, uint32_t y)
{
    uint32_t result = MIX_MULT_L * x - MIX_MULT_R * y;
    result ^= result >> XSHIFT;
    return result;
}

/* generate_state(4, uint64) of the seed sequence with entropy words ``entropy`` (n words,
 * n <= POOL) and spawn key (run,), run < 2**32. */
static void child_state(const uint32_t *entropy, int64_t n, uint32_t run, uint64_t *out)
{
    /* the assembled entropy: the seed's words padded with zeros to the pool's size (a spawn
     * key is there), then the spawn key's word */
    uint32_t words[POOL + 1], pool[POOL];
    for (int i = 0; i < POOL; i++) words[i] = i < n ? entropy[i] : 0u;
    words[POOL] = run;
    uint32_t h = INIT_A;
    for (int i = 0; i < POOL; i++) pool[i] = hashmix(words[i], &h);
    for (int src = 0; src < POOL; src++)
        for (int dst = 0; dst < POOL; dst++)
            if (src != dst) pool[dst] = mix(pool[dst], hashmix(pool[src], &h));
    for (int dst = 0; dst < POOL; dst++) pool[dst] = mix(pool[dst], hashmix(words[POOL], &h));
    /* generate_state: 8 words of 32 bits from the pool, cycled; pairs little-endian */
    uint32_t state[8];
    uint32_t hc = INIT_B;
    for (int i = 0; i < 8; i++) {
        uint32_t v = pool[i % POOL];
        v ^= hc;
        hc *= MULT_B;
        v *= hc;
        v ^= v >> XSHIFT;
        state[i] = v;
    }
    for (int i = 0; i < 4; i++) out[i] = (uint64_t)state[2 * i] | ((uint64_t)state[2 * i + 1] << 32);
}

/* ------------------------------------------------------------------------------------------
 * PCG64 (XSL-RR 128/64) with numpy's bit generator layout
 * ------------------------------------------------------------------------------------------ */

typedef unsigned __int128 u128;

typedef struct {
    u128 state, inc;
    int has_uint32;
    uint32_t uinteger;
} pcg64;

static const u128 PCG_MULT = ((u128)0x2360ed051fc65da4ull << 64) | (u128)0x4385df649fccf645ull;

static void pcg_step(pcg64 *g)
{
    g->state = g->state * PCG_MULT + g->inc;
}

static uint64_t pcg_next64(void *st)
{
    pcg64 *g = (pcg64 *)st;
    pcg_step(g);
    const uint64_t value = (uint64_t)(g->state >> 64) ^ (uint64_t)g->state;
    const unsigned rot = (unsigned)(g->state >> 122);
    return (value >> rot) | (value << ((64u - rot) & 63u));
}

static uint32_t pcg_next32(void *st)
{
    pcg64 *g = (pcg64 *)st;
    if (g->has_uint32) {
        g->has_uint32 = 0;
        return g->uinteger;
    }
    const uint64_t next = pcg_next64(g);
    g->has_uint32 = 1;
    g->uinteger = (uint32_t)(next >> 32);
    return (uint32_t)(next & 0xffffffffu);
}

static double pcg_next_double(void *st)
{
    return (double)(pcg_next64(st) >> 11) * (1.0 / 9007199254740992.0);
}

/* numpy's PCG64 seeded from the four words s: state s[0] s[1], increment s[2] s[3] (high
 * word first), by the generator's srandom: state 0, inc = 2 initseq + 1, a step, state +=
 * initstate, a step. */
static void pcg_seed(pcg64 *g, const uint64_t *s)
{
    const u128 initstate = ((u128)s[0] << 64) | (u128)s[1];
    const u128 initseq = ((u128)s[2] << 64) | (u128)s[3];
    g->state = 0;
    g->inc = (initseq << 1u) | 1u;
    pcg_step(g);
    g->state += initstate;
    pcg_step(g);
    g->has_uint32 = 0;
    g->uinteger = 0;
}

/* numpy/random/bitgen.h's bitgen_t */
typedef struct {
    void *state;
    uint64_t (*next_uint64)(void *st);
    uint32_t (*next_uint32)(void *st);
    double (*next_double)(void *st);
    uint64_t (*next_raw)(void *st);
} np_bitgen;

/* One run's stream of rows, drawn on demand (wk_terrain.extend). */
typedef struct {
    pcg64 g;
    np_bitgen bg;
    const wk_terrain_draws *d;
    double *rows;
    int64_t n_drawn, n_steps;
} drawer;

static void drawer_start(drawer *w, const wk_terrain_draws *d, int64_t run, int64_t n_steps,
                         double *rows)
{
    uint64_t s[4];
    child_state(d->entropy, d->n_entropy, (uint32_t)run, s);
    pcg_seed(&w->g, s);
    w->bg.state = &w->g;
    w->bg.next_uint64 = pcg_next64;
    w->bg.next_uint32 = pcg_next32;
    w->bg.next_double = pcg_next_double;
    w->bg.next_raw = pcg_next64;
    w->d = d;
    w->rows = rows;
    w->n_drawn = 0;
    w->n_steps = n_steps;
}

/* Draws rows up to k (at least: twice those drawn, 16 at first), as walker.analysis.mfpt.draw_terrains
 * computes them: slope mean + std * N, drop height_std * N (0 without); returns the rows
 * drawn.  The stream is sequential, so the rows do not depend on how they are batched. */
static int64_t drawer_extend(void *ctx, int64_t k)
{
    drawer *w = (drawer *)ctx;
    int64_t upto = 2 * w->n_drawn > 16 ? 2 * w->n_drawn : 16;
    if (upto < k) upto = k;
    if (upto > w->n_steps) upto = w->n_steps;
    double (*normal)(void *) = (double (*)(void *))w->d->normal;
    const wk_terrain_draws *d = w->d;
    for (int64_t i = w->n_drawn; i < upto; i++) {
        const double a = normal(&w->bg), b = normal(&w->bg);
        double slope = d->slope_mean, drop = 0.0;
        if (d->slope_std > 0.0) slope += d->slope_std * a;
        if (d->height_std > 0.0) drop = d->height_std * b;
        w->rows[2 * i] = slope;
        w->rows[2 * i + 1] = drop;
    }
    w->n_drawn = upto > w->n_drawn ? upto : w->n_drawn;
    return w->n_drawn;
}

void wk_terrain_draw_rows(const wk_terrain_draws *d, int64_t run, int64_t n_steps, double *rows)
{
    drawer w;
    drawer_start(&w, d, run, n_steps, rows);
    drawer_extend(&w, n_steps);
}

#else

void wk_terrain_draw_rows(const wk_terrain_draws *d, int64_t run, int64_t n_steps, double *rows)
{
    (void)d;
    (void)run;
    wk_terrain_fill_nan(rows, 2 * n_steps);
}

#endif

int wk_terrain_ensemble_drawn(const wk_functions *fn, const wk_terrain_entry *te,
                              const wk_problem *tmpl, const wk_section *sec, const double *z0,
                              const wk_terrain_draws *d, const int64_t *runs, int64_t m,
                              int64_t n_steps, int64_t *status, int64_t *strides)
{
    const int64_t n_x = tmpl->n_x, n_z = sec->n_z;
    double *buf = malloc((size_t)(n_x + n_z + 2 * n_steps) * sizeof(double));
    if (buf == NULL) return WK_ERR_NOMEM;
    double *rows = buf + n_x + n_z;
    int rc = WK_OK;
    for (int64_t i = 0; i < m && rc == WK_OK; i++) {
        if (wk_interrupt) {
            for (int64_t j = i; j < m; j++) {
                status[j] = WK_INTERRUPTED;
                strides[j] = 0;
            }
            break;
        }
        double t;
        const wk_terrain_start st = {z0, 0, NULL};
#ifdef __SIZEOF_INT128__
        drawer w;
        drawer_start(&w, d, runs[i], n_steps, rows);
        rc = wk_terrain_walk_extended(fn, te, tmpl, sec, &st, rows, n_steps, drawer_extend, &w,
                                      status + i, strides + i, &t, buf, buf + n_x);
#else
        wk_terrain_draw_rows(d, runs[i], n_steps, rows);
        rc = wk_terrain_walk(fn, te, tmpl, sec, &st, rows, n_steps, status + i, strides + i, &t,
                             buf, buf + n_x);
#endif
    }
    free(buf);
    return rc;
}
