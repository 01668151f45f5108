/* Terrain defined per step (issue 29): the ground of walker's stride maps when it is not one
 * plane.
 *
 * The rule.  During step n the ground ahead of the stance contact is the plane through the
 * point a height h_n (``drop``, [m], positive down) below the stance contact, with slope
 * gamma_n (``slope``, [rad], downhill positive like the scene's slope).  The step ends at the
 * first touchdown on that plane, under the model's guard and scuff conventions; the next
 * step's pair belongs to the new stance contact.  The state stays in the model's own angle
 * frame (the scene slope's), so the phases' vector fields are the model's: a step's terrain
 * enters only through the guards of touchdown and the ground-referenced quantities of the
 * impact (the normal and tangential impulse directions, the trailing foot's lift-off, the
 * rimless wheel's landing angle).
 *
 * A terrain run calls the model's terrain guards and reset (wk_terrain_entry) with ctx a
 * wk_terrain; the integrator calls wk_terrain_on_stride after every stride event, which
 * moves to the next step.  A step equal to the scene's plane (slope == the scene's slope,
 * drop == 0, the previous step's slope the scene's too) runs the model's plane arithmetic,
 * so plane terrain gives the plane run's numbers bit for bit.
 */
#ifndef WK_TERRAIN_H
#define WK_TERRAIN_H

#include <stdint.h>

#include "batch.h"
#include "hybrid.h"
#include "wk_common.h"
#include "wk_system.h"

/* Largest parameter vector of a model with round feet. */
#define WK_TERRAIN_MAX_P 64

/* The ground of the current step. */
typedef struct {
    double slope;      /* gamma_n [rad], downhill positive */
    double drop;       /* h_n [m]: the plane passes h_n below the stance contact */
    double prev_slope; /* gamma_{n-1}: the plane the stance (trailing) contact stands on */
    double prev_drop;  /* h_{n-1} */
    int plane;         /* the step is the scene's plane: the model's plane arithmetic */
} wk_ground;

/* A terrain run's context (the ctx the model's terrain functions receive). */
typedef struct {
    wk_ground ground;
    const double *steps; /* (n_steps, 2) row-major: (slope, drop) of each step */
    int64_t n_steps;     /* past the last step: the scene's plane */
    int64_t index;       /* the current step */
    double scene_slope;  /* the model's slope parameter [rad] */
    const double *previous; /* (2): the ground before step 0; NULL: the scene's plane */
    /* the model's own ctx (a controller; NULL for the built-in one and the passive models)
     * and, for a model whose phase functions read it (own_ctx), its rhs and jac, called
     * through wk_terrain_rhs / wk_terrain_jac with it */
    void *inner;
    wk_rhs_fn rhs;
    wk_jac_fn jac;
    /* round feet (the entry's radius_index, p[radius_index] > 0): the stance leg's angle
     * x[0] when the step began (its foot has rolled from there), and the parameters with
     * the slope of the plane the stance foot rolls on, for the model's phase functions */
    double land_angle;
    int rolling;
    int64_t n_params;
    int64_t slope_index;
    double p_buf[WK_TERRAIN_MAX_P];
    /* rows drawn as the walk needs them (terrain_draw.c; NULL: steps holds them all):
     * extend(extend_ctx, k) fills steps up to row k at least and returns the rows filled,
     * n_ready */
    int64_t (*extend)(void *extend_ctx, int64_t k);
    void *extend_ctx;
    int64_t n_ready;
} wk_terrain;

/* A model's terrain functions: guards and reset with the signatures of wk_system.h, called
 * with ctx a wk_terrain (the model's own ctx is NULL: passive models only). */
typedef struct {
    const char *name;     /* the model (registry name, WK_ENTRY_NAME_*, wk_registry.h) */
    wk_guards_fn guards;  /* the model's plane guards: the key the run is found by */
    int64_t slope_index;  /* the slope's index in the parameter vector */
    wk_guards_fn terrain_guards;
    wk_reset_fn terrain_reset;
    int own_ctx; /* the model's rhs, jac, guards and reset read a ctx of their own */
    /* round feet: the foot radius' index in p (-1: point feet only) and the parameters'
     * count; with p[radius_index] > 0 the phase functions run with the slope of the plane
     * the stance foot rolls on (wk_terrain_rolling_rhs) */
    int64_t radius_index;
    int64_t n_params;
    /* a section lift (and its Jacobian) for terrain runs of a model whose registry entry
     * has none (wk_models.h; the five-link walker's: its lift solves for the swing tibia's
     * angle), NULL otherwise: walker/simulation/_terrain_run.py passes them to the section settings */
    wk_state_fn lift;
    wk_state_fn lift_jacobian;
} wk_terrain_entry;

/* The run's functions: the model's with its terrain guards and reset, ctx T (T's inner,
 * rhs and jac set from fn, its land_angle from the start state x0, its rolling from p),
 * on_stride wk_terrain_on_stride; rhs and jac go through the trampolines below for a model
 * with a ctx of its own, or with the stance plane's parameters for round feet. */
wk_functions wk_terrain_functions(const wk_functions *fn, const wk_terrain_entry *te,
                                  wk_terrain *T, const double *p, const double *x0);

/* The model's rhs and jac with T->inner as their ctx (ctx a wk_terrain). */
void wk_terrain_rhs(int64_t phase, double t, const double *x, const double *p, double *dx,
                    void *ctx);
void wk_terrain_jac(int64_t phase, double t, const double *x, const double *p, double *J,
                    void *ctx);

/* impulse (2) along and normal to the plane of slope ``from`` -> the same impulse along and
 * normal to the plane of slope ``to`` [rad]. */
void wk_terrain_rotate_impulse(double *impulse, double from, double to);

/* The terrain functions of the model whose plane guards are ``guards``; NULL: none. */
const wk_terrain_entry *wk_terrain_find(wk_guards_fn guards);

/* Sets the ground of step ``index`` (the previous step's from index - 1, the scene's plane
 * before step 0 and past the last step). */
void wk_terrain_set_step(wk_terrain *T, int64_t index);

/* wk_stride_fn: the next step after a stride (and the new stance leg's angle x[0]). */
void wk_terrain_on_stride(void *ctx, int64_t n_done, const double *x);

/* The parameters with the slope of the plane the stance foot stands on (T->p_buf) for a
 * walker with round feet, else p itself. */
const double *wk_terrain_stance_params(wk_terrain *T, const double *p);

/* The signed distance [m] of a round swing foot's lowest point from the step's plane, from
 * the foot centres' offset (L - R)(cos(q_st + gamma) - cos(q_sw + gamma)) (``centres``,
 * computed with the step's slope gamma): the stance foot rolled R (land_angle - q_st)
 * along the plane of slope gamma_s it stands on, from the contact it landed at. */
double wk_terrain_round_height(const wk_terrain *T, double centres, double q_stance, double R);

/* wk_terrain_heel_strike for round feet: the swing foot's contact on the step's plane, the
 * trailing foot's on the previous step's, the hip's velocity from the stance foot rolling
 * on it. */
int64_t wk_terrain_heel_strike_round(const wk_floating_base *B, const int *swap, int n_c,
                                     const double *x, const double *p, const wk_terrain *T,
                                     double *x_new, double *impulse);

/* Recomputes ground.plane from the values in ground (after they were changed). */
void wk_terrain_update_plane(wk_terrain *T);

/* Where a walk starts: ``from_state`` 0, at the section point start (n_z; sec's lift), else
 * at the full state start (n_x); the start checks of wk_section_start either way.
 * ``previous`` (2) the (slope, drop) of the step the start landed on, NULL: the scene's
 * plane. */
typedef struct {
    const double *start;
    int from_state;
    const double *previous;
} wk_terrain_start;

/* wk_terrain_walk over rows that extend(extend_ctx, k) fills as the walk reaches them (rows
 * 0 .. k - 1 of ``steps`` at least; it returns how many are filled; see wk_terrain.extend). */
int wk_terrain_walk_extended(const wk_functions *fn, const wk_terrain_entry *te,
                             const wk_problem *tmpl, const wk_section *sec,
                             const wk_terrain_start *st, const double *steps, int64_t n_steps,
                             int64_t (*extend)(void *, int64_t), void *extend_ctx, int64_t *status,
                             int64_t *strides, double *t, double *x, double *z_out);

/* Walks from ``st`` over the n_steps steps of ``steps``, one integration of n_steps strides.
 * Fills status, strides (completed), t, the final state x (n_x) and section point z_out
 * (n_z, NaN unless completed).  Returns a wk_hybrid_solve code. */
int wk_terrain_walk(const wk_functions *fn, const wk_terrain_entry *te, const wk_problem *tmpl,
                    const wk_section *sec, const wk_terrain_start *st, const double *steps,
                    int64_t n_steps, int64_t *status, int64_t *strides, double *t, double *x,
                    double *z_out);

/* As wk_terrain_walk with the Jacobians, stride by stride: jz (n_z, n_0) d z_out / d start
 * (n_0 = n_z from a section point, n_x from a state) and
 * tjac (n_z, 2 n_steps) d z_out / d (slope_k, drop_k), column 2k the slope and 2k + 1 the
 * drop of step k: the variational equations and saltation matrices of each stride
 * (wk_hybrid_solve) and, at each stride's touchdown, the terrain's terms (the guard's and
 * the reset's dependence on the step's pair) by Richardson-extrapolated central
 * differences.  Returns a wk_hybrid_solve code (WK_ERR_NOMEM). */
int wk_terrain_walk_jac(const wk_functions *fn, const wk_terrain_entry *te,
                        const wk_problem *tmpl, const wk_section *sec, const wk_terrain_start *st,
                        const double *steps, int64_t n_steps, int64_t *status, int64_t *strides,
                        double *t, double *x, double *z_out, double *jz, double *tjac);

/* Shared by terrain.c and terrain_jac.c: T for a walk over steps (the ground of step 0;
 * ``previous`` the ground before it, NULL: the scene's plane); the start of a walk, x (n_x)
 * and its phase, 0 or the status of a start not integrated; v[0..n) = NaN. */
void wk_terrain_init(wk_terrain *T, const wk_terrain_entry *te, const wk_problem *tmpl,
                     const double *steps, int64_t n_steps, const double *previous);
int64_t wk_terrain_walk_start(const wk_problem *tmpl, const wk_section *sec,
                              const wk_terrain_start *st, double *x, int64_t *phase0);
void wk_terrain_fill_nan(double *v, int64_t n);

/* Many walks (Monte Carlo): run i from z0 (n_z) over steps + i * n_steps * 2; status[i] and
 * strides[i] (completed strides before the first failure).  Polls wk_interrupt (hybrid.h)
 * before each run and, through the integrator, every step: after a signal the run being
 * walked and every later one end with WK_INTERRUPTED.  Returns a wk_hybrid_solve
 * code. */
int wk_terrain_ensemble(const wk_functions *fn, const wk_terrain_entry *te,
                        const wk_problem *tmpl, const wk_section *sec, const double *z0,
                        int64_t m, const double *steps, int64_t n_steps, int64_t *status,
                        int64_t *strides);

/* Terrain draws in compiled code (terrain_draw.c): walker.analysis.mfpt's per-run rows, run i's from
 * the i-th child of numpy.random.SeedSequence(seed) (entropy: the seed's 32-bit words, at
 * most 4, least significant first), slope slope_mean + slope_std N and drop height_std N
 * per step; ``normal`` numpy's random_standard_normal(bitgen_t *). */
typedef struct {
    const uint32_t *entropy;
    int64_t n_entropy;
    double slope_mean, slope_std, height_std;
    void *normal;
} wk_terrain_draws;

/* 1 when this build draws (128-bit integers), else 0. */
int wk_terrain_draws_supported(void);

/* Run ``run``'s first n_steps rows (n_steps, 2) into rows. */
void wk_terrain_draw_rows(const wk_terrain_draws *d, int64_t run, int64_t n_steps, double *rows);

/* wk_terrain_ensemble with the rows drawn here: run i (runs[i], the child's index) from z0
 * (n_z) over its first n_steps rows; status[i], strides[i].  Polls wk_interrupt as
 * wk_terrain_ensemble.  Returns a wk_hybrid_solve code. */
int wk_terrain_ensemble_drawn(const wk_functions *fn, const wk_terrain_entry *te,
                              const wk_problem *tmpl, const wk_section *sec, const double *z0,
                              const wk_terrain_draws *d, const int64_t *runs, int64_t m,
                              int64_t n_steps, int64_t *status, int64_t *strides);

/* The terrain's heel strike of a floating-base walker (wk_plastic_heel_strike on terrain):
 * the impact of B at x (n_c coordinates and their rates) and the leg swap into x_new; the
 * impulse (along, normal to the step's plane G->slope) and the trailing foot's lift-off
 * from the plane it stands on (G->prev_slope).  Returns a status: 0, NONPHYSICAL_IMPACT
 * (impulse[1] <= 0 or no lift-off) or LINEAR_SOLVE_FAILED. */
int64_t wk_terrain_heel_strike(const wk_floating_base *B, const int *swap, int n_c,
                               const double *x, const double *p, const wk_ground *G,
                               double *x_new, double *impulse);

/* The model terrain functions (defined in the model files). */
#define WK_DECLARE_TERRAIN(name)                                                             \
    void wk_terrain_##name##_guards(int64_t phase, double t, const double *x, const double *p, \
                                    double *g, void *ctx);                                   \
    void wk_terrain_##name##_reset(int64_t phase, int64_t k, double t, const double *x,      \
                                   const double *p, double *x_new, double *impulse,          \
                                   int64_t *out, void *ctx);

/* Defines wk_terrain_<name>_guards and _reset (declared by WK_DECLARE_TERRAIN) for a model
 * file whose static terrain_guards(K, phase, x, p, g, T) and
 * terrain_reset(K, phase, k, x, p, x_new, impulse, out, T) take its kernels K (here &KT, a
 * static table of the file) and the wk_terrain T (the ctx). */
#define WK_DEFINE_TERRAIN(name, KT)                                                           \
    void wk_terrain_##name##_guards(int64_t phase, double t, const double *x, const double *p, \
                                    double *g, void *ctx)                                    \
    {                                                                                        \
        (void)t;                                                                             \
        terrain_guards(&KT, phase, x, p, g, (const wk_terrain *)ctx);                        \
    }                                                                                        \
    void wk_terrain_##name##_reset(int64_t phase, int64_t k, double t, const double *x,      \
                                   const double *p, double *x_new, double *impulse,          \
                                   int64_t *out, void *ctx)                                  \
    {                                                                                        \
        (void)t;                                                                             \
        terrain_reset(&KT, phase, k, x, p, x_new, impulse, out, (const wk_terrain *)ctx);    \
    }
/* Entries written in their model files (their plane guards are static there). */
extern const wk_terrain_entry wk_terrain_entry_compass_coulomb;
extern const wk_terrain_entry wk_terrain_entry_kneed_coulomb;
extern const wk_terrain_entry wk_terrain_entry_three_link;
extern const wk_terrain_entry wk_terrain_entry_five_link;

WK_DECLARE_TERRAIN(rimless_wheel)
WK_DECLARE_TERRAIN(simplest)
WK_DECLARE_TERRAIN(compass)
WK_DECLARE_TERRAIN(compass_plain)
WK_DECLARE_TERRAIN(kneed)
WK_DECLARE_TERRAIN(kneed_plain)
WK_DECLARE_TERRAIN(kneed_ignore_scuff)
WK_DECLARE_TERRAIN(kneed_plain_ignore_scuff)

#endif
