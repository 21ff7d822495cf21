// The fixture of the Bullet wrapper's tests (tests/test_phys_*.c): a world whose log callback
// keeps the last message, assertions that print what they compared, and small builders.
//
// Each test builds a small world, runs it, and checks one behaviour against a
// number worked out by hand (in the comment next to it). Header only: every helper is
// static (inline), so each test program keeps what it uses.
#ifndef SEICHE_TESTS_PHYS_FIXTURE_H
#define SEICHE_TESTS_PHYS_FIXTURE_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fluid/bullet/phys.h"

#define G 9.81
#define PI 3.14159265358979323846

// ---- helpers ------------------------------------------------------------------

#define assert_near(got, want, tol)                                                     \
    do {                                                                                \
        const double got_ = (double)(got), want_ = (double)(want), tol_ = (double)(tol); \
        if (!(fabs(got_ - want_) <= tol_)) {                                            \
            fail_msg("%s = %.9g, expected %.9g within %g", #got, got_, want_, tol_);    \
        }                                                                               \
    } while (0)

#define assert_contains(text, part)                                                 \
    do {                                                                            \
        const char *text_ = (text);                                                 \
        if (!strstr(text_, (part))) fail_msg("\"%s\" does not contain \"%s\"", text_, (part)); \
    } while (0)

#define assert_ok(expr)                                                             \
    do {                                                                            \
        const phys_result r_ = (expr);                                              \
        if (r_ != PHYS_OK) fail_msg("%s returned %s", #expr, phys_result_string(r_)); \
    } while (0)

typedef struct fixture {
    phys_world *world;
    char log[1024];   // last message given to the log callback
    int log_count;
} fixture;

static inline void capture_log(void *user, phys_log_level level, const char *message) {
    fixture *f = user;
    (void)level;
    snprintf(f->log, sizeof f->log, "%s", message);
    f->log_count++;
}

static inline int setup(void **state) {
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    phys_world_def def = phys_default_world_def();
    def.log = capture_log;
    def.log_user = f;
    if (phys_world_create(&def, &f->world) != PHYS_OK) {
        free(f);
        return -1;
    }
    *state = f;
    return 0;
}

static inline int teardown(void **state) {
    fixture *f = *state;
    phys_world_destroy(f->world);
    free(f);
    return 0;
}

static const phys_vec3 zero3 = {0, 0, 0};
static const phys_quat identity = {0, 0, 0, 1};

static inline phys_vec3 v3(float x, float y, float z) {
    phys_vec3 v = {x, y, z};
    return v;
}

static inline phys_shape_id make_sphere(phys_world *w, float radius) {
    phys_sphere s = {radius};
    phys_shape_id id = {0, 0, 0};
    assert_ok(phys_shape_create_sphere(w, &s, &id));
    return id;
}

static inline phys_shape_id make_box(phys_world *w, float hx, float hy, float hz) {
    phys_box b = {{hx, hy, hz}};
    phys_shape_id id = {0, 0, 0};
    assert_ok(phys_shape_create_box(w, &b, &id));
    return id;
}

// Ground plane y = 0 on a static body.
static inline phys_body_id make_ground(phys_world *w) {
    phys_plane p = {{0, 1, 0}, 0};
    phys_shape_id shape = {0, 0, 0};
    assert_ok(phys_shape_create_plane(w, &p, &shape));
    phys_body_def def = phys_default_body_def();
    def.type = PHYS_BODY_STATIC;
    def.shape = shape;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static inline phys_body_id make_body(phys_world *w, phys_body_type type, phys_shape_id shape,
                                     phys_vec3 position) {
    phys_body_def def = phys_default_body_def();
    def.type = type;
    def.shape = shape;
    def.position = position;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static inline phys_vec3 position_of(phys_world *w, phys_body_id id) {
    phys_vec3 p = zero3;
    assert_ok(phys_body_get_pose(w, id, &p, NULL));
    return p;
}

static inline phys_vec3 velocity_of(phys_world *w, phys_body_id id) {
    phys_vec3 v = zero3;
    assert_ok(phys_body_get_linear_velocity(w, id, &v));
    return v;
}

static inline void run(phys_world *w, float dt, int steps) {
    for (int i = 0; i < steps; ++i) assert_ok(phys_world_step(w, dt));
}

#endif
