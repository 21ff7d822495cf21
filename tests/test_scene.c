// Scene graph, camera and input, without GL: transforms compose parent -> child, destroying
// a parent takes its subtree with it, stale ids are refused, the camera's view matrix puts
// what it looks at straight ahead, and injected input drives the orbit and fly controls.
#include "tests/support.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <string.h>

#include "engine/render/camera.h"
#include "engine/gl/input.h"
#include "engine/render/scene.h"

#define EPS 1e-4f

typedef struct fixture {
    support_log log;
    eng_scene *scene;
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof f);
    eng_scene_def def = eng_default_scene_def();
    def.logger = support_capture_logger(&f.log);
    f.scene = eng_scene_create(&def);
    *state = &f;
    return f.scene ? 0 : -1;
}

static int teardown(void **state)
{
    fixture *f = *state;
    eng_scene_destroy(f->scene);
    return 0;
}

static void assert_vec3_near(const float *a, float x, float y, float z, float eps)
{
    if (fabsf(a[0] - x) > eps || fabsf(a[1] - y) > eps || fabsf(a[2] - z) > eps)
        fail_msg("got (%g, %g, %g), expected (%g, %g, %g)", (double)a[0], (double)a[1], (double)a[2], (double)x,
                 (double)y, (double)z);
}

static eng_node_id make(eng_scene *s, eng_node_id parent, float tx, float ty, float tz)
{
    eng_node_def d = eng_default_node_def();
    d.parent = parent;
    d.local.translation[0] = tx, d.local.translation[1] = ty, d.local.translation[2] = tz;
    return eng_node_create(s, &d);
}

static void child_world_transform_composes_rotated_translated_scaled_parent(void **state)
{
    fixture *f = *state;
    // Parent: scale 2, then 90 degrees about +Y, then move to (1, 2, 3).
    eng_node_def pd = eng_default_node_def();
    pd.local.translation[0] = 1, pd.local.translation[1] = 2, pd.local.translation[2] = 3;
    float s = sinf(GLM_PI_4f), c = cosf(GLM_PI_4f); // half angle of 90 degrees
    pd.local.rotation[0] = 0, pd.local.rotation[1] = s, pd.local.rotation[2] = 0, pd.local.rotation[3] = c;
    pd.local.scale[0] = pd.local.scale[1] = pd.local.scale[2] = 2.0f;
    eng_node_id parent = eng_node_create(f->scene, &pd);
    assert_true(eng_node_is_valid(f->scene, parent));
    eng_node_id child = make(f->scene, parent, 1.0f, 0.0f, 0.0f);
    assert_true(eng_node_is_valid(f->scene, child));

    // By hand: (1,0,0) scaled -> (2,0,0); +90 deg about Y sends +X to -Z -> (0,0,-2);
    // translated -> (1, 2, 1).
    mat4 w;
    assert_true(eng_node_get_world(f->scene, child, w));
    assert_vec3_near(w[3], 1.0f, 2.0f, 1.0f, EPS);
    // The child's own +X axis points along world -Z, scaled by 2.
    assert_vec3_near(w[0], 0.0f, 0.0f, -2.0f, EPS);

    // Moving the parent moves the child (world matrices are recomputed).
    eng_transform t = eng_node_get_local(f->scene, parent);
    t.translation[1] = 5.0f;
    assert_true(eng_node_set_local(f->scene, parent, &t));
    assert_true(eng_node_get_world(f->scene, child, w));
    assert_vec3_near(w[3], 1.0f, 5.0f, 1.0f, EPS);

    // A grandchild with its own rotation: -90 deg about Y cancels the parent's rotation.
    eng_node_def gd = eng_default_node_def();
    gd.parent = child;
    gd.local.rotation[1] = -s, gd.local.rotation[3] = c;
    gd.local.translation[2] = 1.0f;
    eng_node_id grandchild = eng_node_create(f->scene, &gd);
    assert_true(eng_node_get_world(f->scene, grandchild, w));
    // (0,0,1) in the child's frame: scale 2 -> (0,0,2), +90 deg about Y: +Z -> +X -> (2,0,0),
    // plus the child's world position (1,5,1) -> (3, 5, 1).
    assert_vec3_near(w[3], 3.0f, 5.0f, 1.0f, EPS);
    assert_vec3_near(w[0], 2.0f, 0.0f, 0.0f, EPS); // rotations cancel, scale 2 stays
    eng_node_destroy(f->scene, parent);
}

static void destroying_a_parent_destroys_and_invalidates_its_subtree(void **state)
{
    fixture *f = *state;
    int before = eng_scene_node_count(f->scene);
    eng_node_id root = make(f->scene, ENG_NULL_NODE, 0, 0, 0);
    eng_node_id a = make(f->scene, root, 1, 0, 0);
    eng_node_id b = make(f->scene, root, 2, 0, 0);
    eng_node_id a1 = make(f->scene, a, 0, 1, 0);
    eng_node_id a2 = make(f->scene, a, 0, 2, 0);
    eng_node_id other = make(f->scene, ENG_NULL_NODE, 5, 0, 0);
    assert_int_equal(eng_scene_node_count(f->scene), before + 6);

    eng_node_destroy(f->scene, a); // a middle node: a, a1, a2 go; root and b stay
    assert_false(eng_node_is_valid(f->scene, a));
    assert_false(eng_node_is_valid(f->scene, a1));
    assert_false(eng_node_is_valid(f->scene, a2));
    assert_true(eng_node_is_valid(f->scene, root));
    assert_true(eng_node_is_valid(f->scene, b));
    assert_int_equal(eng_scene_node_count(f->scene), before + 3);

    eng_node_destroy(f->scene, root);
    assert_false(eng_node_is_valid(f->scene, root));
    assert_false(eng_node_is_valid(f->scene, b));
    assert_true(eng_node_is_valid(f->scene, other));
    assert_int_equal(eng_scene_node_count(f->scene), before + 1);

    // Iteration sees exactly the live nodes.
    int seen = 0;
    for (eng_node_id n = eng_scene_first(f->scene); n.index1; n = eng_scene_next(f->scene, n)) {
        assert_true(eng_node_is_valid(f->scene, n));
        seen++;
    }
    assert_int_equal(seen, eng_scene_node_count(f->scene));
    eng_node_destroy(f->scene, other);
}

static void stale_and_null_ids_are_rejected_with_a_message(void **state)
{
    fixture *f = *state;
    eng_node_id old = make(f->scene, ENG_NULL_NODE, 0, 0, 0);
    eng_node_destroy(f->scene, old);
    eng_node_id reused = make(f->scene, ENG_NULL_NODE, 0, 0, 0);
    // The slot is reused, with a new generation: the old id stays dead.
    assert_int_equal(reused.index1, old.index1);
    assert_int_not_equal(reused.generation, old.generation);
    assert_false(eng_node_is_valid(f->scene, old));
    assert_true(eng_node_is_valid(f->scene, reused));
    assert_false(eng_node_is_valid(f->scene, ENG_NULL_NODE));

    support_log_clear(&f->log);
    eng_transform t = eng_identity_transform();
    t.translation[0] = 9.0f;
    assert_false(eng_node_set_local(f->scene, old, &t));
    assert_true(support_log_contains(&f->log, "eng_node_set_local: attempt to use a destroyed node"));
    mat4 w;
    assert_false(eng_node_get_world(f->scene, old, w));
    // The stale write did not land on the node now in that slot.
    assert_true(eng_node_get_world(f->scene, reused, w));
    assert_float_equal(w[3][0], 0.0f, EPS);

    // A stale parent is refused at creation, naming the field.
    support_log_clear(&f->log);
    eng_node_def d = eng_default_node_def();
    d.parent = old;
    eng_node_id n = eng_node_create(f->scene, &d);
    assert_int_equal(n.index1, 0);
    assert_true(support_log_contains(&f->log, "eng_node_def.parent"));

    // Destroying twice is reported and harmless.
    support_log_clear(&f->log);
    eng_node_destroy(f->scene, old);
    assert_true(support_log_contains(&f->log, "attempt to use a destroyed node"));
    assert_true(eng_node_is_valid(f->scene, reused));
    eng_node_destroy(f->scene, reused);
}

static void bad_node_defs_are_refused_naming_the_field(void **state)
{
    fixture *f = *state;
    eng_node_def d = eng_default_node_def();
    d.local.rotation[3] = 2.0f; // not a unit quaternion
    support_log_clear(&f->log);
    assert_int_equal(eng_node_create(f->scene, &d).index1, 0);
    assert_true(support_log_contains(&f->log, "eng_node_def.local.rotation must be a unit quaternion"));

    d = eng_default_node_def();
    d.local.scale[1] = 0.0f;
    support_log_clear(&f->log);
    assert_int_equal(eng_node_create(f->scene, &d).index1, 0);
    assert_true(support_log_contains(&f->log, "eng_node_def.local.scale[1] must be finite and non-zero (got 0)"));

    d = eng_default_node_def();
    d.color[2] = 1.5f;
    support_log_clear(&f->log);
    assert_int_equal(eng_node_create(f->scene, &d).index1, 0);
    assert_true(support_log_contains(&f->log, "eng_node_def.color[2] must be 0..1 (got 1.5)"));
}

static void reparenting_under_a_descendant_is_refused(void **state)
{
    fixture *f = *state;
    eng_node_id a = make(f->scene, ENG_NULL_NODE, 1, 0, 0);
    eng_node_id b = make(f->scene, a, 1, 0, 0);
    support_log_clear(&f->log);
    assert_false(eng_node_set_parent(f->scene, a, b));
    assert_true(support_log_contains(&f->log, "descendants"));
    // Moving b to the top level keeps its local transform: world x becomes 1.
    assert_true(eng_node_set_parent(f->scene, b, ENG_NULL_NODE));
    mat4 w;
    assert_true(eng_node_get_world(f->scene, b, w));
    assert_float_equal(w[3][0], 1.0f, EPS);
    assert_int_equal(eng_node_get_parent(f->scene, b).index1, 0);
    eng_node_destroy(f->scene, a);
    assert_true(eng_node_is_valid(f->scene, b));
    eng_node_destroy(f->scene, b);
}

static void camera_view_puts_the_target_straight_ahead(void **state)
{
    (void)state;
    eng_camera cam;
    eng_camera_def def = eng_default_camera_def();
    def.position[0] = 3, def.position[1] = 4, def.position[2] = 5;
    def.target[0] = 1, def.target[1] = 1, def.target[2] = -1;
    char err[256];
    assert_true(eng_camera_init(&cam, &def, err, sizeof err));
    mat4 view, proj;
    eng_camera_view(&cam, view);
    float d = sqrtf(4.0f + 9.0f + 36.0f); // |target - eye| = 7
    vec4 t = { 1, 1, -1, 1 }, tv;
    glm_mat4_mulv(view, t, tv);
    assert_vec3_near(tv, 0.0f, 0.0f, -d, 1e-3f); // straight down -Z of view space
    vec4 e = { 3, 4, 5, 1 }, ev;
    glm_mat4_mulv(view, e, ev);
    assert_vec3_near(ev, 0.0f, 0.0f, 0.0f, 1e-4f);
    // World up stays up on screen: a point above the target is above the centre.
    vec4 up = { 1, 2, -1, 1 }, upv;
    glm_mat4_mulv(view, up, upv);
    assert_true(upv[1] > 0.1f);
    // Projected, the target lands in the middle of the screen, inside the depth range.
    eng_camera_projection(&cam, 16.0f / 9.0f, proj);
    vec4 clip;
    glm_mat4_mulv(proj, tv, clip);
    assert_float_equal(clip[0] / clip[3], 0.0f, 1e-4f);
    assert_float_equal(clip[1] / clip[3], 0.0f, 1e-4f);
    assert_true(fabsf(clip[2] / clip[3]) < 1.0f);

    // A camera at (0, 0, 5) looking at the origin: +X of the world is to the right.
    eng_camera_look_at(&cam, (const float[]){ 0, 0, 5 }, (const float[]){ 0, 0, 0 });
    eng_camera_view(&cam, view);
    vec4 right = { 1, 0, 0, 1 }, rv;
    glm_mat4_mulv(view, right, rv);
    assert_vec3_near(rv, 1.0f, 0.0f, -5.0f, 1e-4f);
}

static void camera_def_out_of_range_is_refused_naming_the_field(void **state)
{
    (void)state;
    eng_camera cam;
    char err[256];
    eng_camera_def def = eng_default_camera_def();
    def.fov_y = 0.0f;
    assert_false(eng_camera_init(&cam, &def, err, sizeof err));
    assert_non_null(strstr(err, "eng_camera_def.fov_y must be 0.01..3.1 radians (got 0)"));
    def = eng_default_camera_def();
    def.far_plane = def.near_plane;
    assert_false(eng_camera_init(&cam, &def, err, sizeof err));
    assert_non_null(strstr(err, "eng_camera_def.far_plane"));
    def = eng_default_camera_def();
    memcpy(def.target, def.position, sizeof def.target);
    assert_false(eng_camera_init(&cam, &def, err, sizeof err));
    assert_non_null(strstr(err, "eng_camera_def.target"));
}

static void key(eng_input *in, int k, int action)
{
    eng_event e = { .type = ENG_EVENT_KEY, .key = k, .action = action };
    eng_input_inject(in, &e);
}

static void button(eng_input *in, int b, int action)
{
    eng_event e = { .type = ENG_EVENT_MOUSE_BUTTON, .button = b, .action = action };
    eng_input_inject(in, &e);
}

static void motion(eng_input *in, double x, double y)
{
    eng_event e = { .type = ENG_EVENT_MOTION, .x = x, .y = y };
    eng_input_inject(in, &e);
}

static void input_tracks_state_per_frame_and_queues_events_in_order(void **state)
{
    (void)state;
    eng_input *in = eng_input_create(NULL); // headless: all zero until events arrive
    assert_non_null(in);
    assert_false(eng_input_key_down(in, GLFW_KEY_W));
    double x, y;
    eng_input_mouse_delta(in, &x, &y);
    assert_true(x == 0.0 && y == 0.0);

    eng_input_begin_frame(in);
    key(in, GLFW_KEY_W, ENG_PRESS);
    motion(in, 100, 50);
    motion(in, 110, 47);
    eng_event sc = { .type = ENG_EVENT_SCROLL, .dy = 2.0 };
    eng_input_inject(in, &sc);
    assert_true(eng_input_key_down(in, GLFW_KEY_W));
    assert_true(eng_input_key_pressed(in, GLFW_KEY_W));
    eng_input_mouse_delta(in, &x, &y);
    assert_true(x == 10.0 && y == -3.0); // the first position only sets the origin
    eng_input_scroll(in, &x, &y);
    assert_true(y == 2.0);

    eng_input_begin_frame(in); // next frame: still down, no longer "pressed"; motion reset
    assert_true(eng_input_key_down(in, GLFW_KEY_W));
    assert_false(eng_input_key_pressed(in, GLFW_KEY_W));
    eng_input_mouse_delta(in, &x, &y);
    assert_true(x == 0.0 && y == 0.0);
    key(in, GLFW_KEY_W, ENG_RELEASE);
    assert_false(eng_input_key_down(in, GLFW_KEY_W));

    eng_event e;
    const eng_event_type order[] = { ENG_EVENT_KEY, ENG_EVENT_MOTION, ENG_EVENT_MOTION, ENG_EVENT_SCROLL, ENG_EVENT_KEY };
    assert_int_equal(eng_input_queued(in), 5);
    for (int i = 0; i < 5; i++) {
        assert_true(eng_input_next_event(in, &e));
        assert_int_equal(e.type, order[i]);
        if (i == 2) assert_true(e.dx == 10.0 && e.dy == -3.0);
        if (i == 4) assert_int_equal(e.action, ENG_RELEASE);
    }
    assert_false(eng_input_next_event(in, &e));

    for (int i = 0; i < ENG_INPUT_QUEUE_CAPACITY + 5; i++) motion(in, i, 0);
    assert_int_equal(eng_input_queued(in), ENG_INPUT_QUEUE_CAPACITY);
    assert_int_equal(eng_input_dropped(in), 5);
    eng_input_destroy(in);
}

static void orbit_drag_turns_around_the_target_and_scroll_zooms(void **state)
{
    (void)state;
    eng_camera cam;
    eng_camera_def def = eng_default_camera_def();
    def.position[0] = 0, def.position[1] = 0, def.position[2] = 10;
    def.target[0] = 0, def.target[1] = 0, def.target[2] = 0;
    def.look_speed = 0.01f;
    def.zoom_step = 0.1f;
    assert_true(eng_camera_init(&cam, &def, NULL, 0));
    eng_input *in = eng_input_create(NULL);

    // Moving the mouse without a button does nothing.
    eng_input_begin_frame(in);
    motion(in, 0, 0);
    motion(in, 50, 0);
    eng_camera_update(&cam, in, 1.0f / 60.0f);
    assert_vec3_near(cam.position, 0.0f, 0.0f, 10.0f, 1e-4f);

    // Dragging right by 157 px at 0.01 rad/px swings the eye a quarter turn, to -X.
    eng_input_begin_frame(in);
    button(in, GLFW_MOUSE_BUTTON_LEFT, ENG_PRESS);
    motion(in, 50.0 + 100.0 * GLM_PI_2, 0);
    eng_camera_update(&cam, in, 1.0f / 60.0f);
    assert_vec3_near(cam.position, -10.0f, 0.0f, 0.0f, 1e-3f);
    assert_float_equal(cam.distance, 10.0f, 1e-4f);
    mat4 view;
    eng_camera_view(&cam, view);
    vec4 o = { 0, 0, 0, 1 }, ov;
    glm_mat4_mulv(view, o, ov);
    assert_vec3_near(ov, 0.0f, 0.0f, -10.0f, 1e-3f); // still looking at the target

    // Two scroll steps towards the scene: distance x 0.9^2.
    eng_input_begin_frame(in);
    button(in, GLFW_MOUSE_BUTTON_LEFT, ENG_RELEASE);
    eng_event sc = { .type = ENG_EVENT_SCROLL, .dy = 2.0 };
    eng_input_inject(in, &sc);
    eng_camera_update(&cam, in, 1.0f / 60.0f);
    assert_float_equal(cam.distance, 8.1f, 1e-3f);
    assert_vec3_near(cam.position, -8.1f, 0.0f, 0.0f, 1e-3f);
    eng_input_destroy(in);
}

static void fly_mode_moves_with_wasd_and_looks_with_the_right_button(void **state)
{
    (void)state;
    eng_camera cam;
    eng_camera_def def = eng_default_camera_def();
    def.mode = ENG_CAMERA_FLY;
    def.position[0] = 0, def.position[1] = 1, def.position[2] = 0;
    def.target[0] = 0, def.target[1] = 1, def.target[2] = -1; // looking down -Z
    def.move_speed = 2.0f;
    def.look_speed = 0.01f;
    assert_true(eng_camera_init(&cam, &def, NULL, 0));
    eng_input *in = eng_input_create(NULL);

    eng_input_begin_frame(in);
    key(in, GLFW_KEY_W, ENG_PRESS);
    eng_camera_update(&cam, in, 0.5f); // 2 m/s for 0.5 s: 1 m forward
    assert_vec3_near(cam.position, 0.0f, 1.0f, -1.0f, 1e-4f);
    key(in, GLFW_KEY_W, ENG_RELEASE);
    key(in, GLFW_KEY_E, ENG_PRESS);
    key(in, GLFW_KEY_D, ENG_PRESS);
    eng_camera_update(&cam, in, 0.5f); // up and right together: 1 m along the diagonal
    float h = 1.0f / sqrtf(2.0f);
    assert_vec3_near(cam.position, h, 1.0f + h, -1.0f, 1e-4f);
    key(in, GLFW_KEY_E, ENG_RELEASE);
    key(in, GLFW_KEY_D, ENG_RELEASE);

    // Mouse look needs the right button: 157 px to the right turns a quarter, to +X.
    eng_input_begin_frame(in);
    motion(in, 0, 0);
    motion(in, 100.0 * GLM_PI_2, 0);
    eng_camera_update(&cam, in, 0.0f);
    float fwd[3];
    eng_camera_forward(&cam, fwd);
    assert_vec3_near(fwd, 0.0f, 0.0f, -1.0f, 1e-4f);
    eng_input_begin_frame(in);
    button(in, GLFW_MOUSE_BUTTON_RIGHT, ENG_PRESS);
    motion(in, 200.0 * GLM_PI_2, 0);
    eng_camera_update(&cam, in, 0.0f);
    eng_camera_forward(&cam, fwd);
    assert_vec3_near(fwd, 1.0f, 0.0f, 0.0f, 1e-3f);
    eng_input_destroy(in);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(child_world_transform_composes_rotated_translated_scaled_parent),
        cmocka_unit_test(destroying_a_parent_destroys_and_invalidates_its_subtree),
        cmocka_unit_test(stale_and_null_ids_are_rejected_with_a_message),
        cmocka_unit_test(bad_node_defs_are_refused_naming_the_field),
        cmocka_unit_test(reparenting_under_a_descendant_is_refused),
        cmocka_unit_test(camera_view_puts_the_target_straight_ahead),
        cmocka_unit_test(camera_def_out_of_range_is_refused_naming_the_field),
        cmocka_unit_test(input_tracks_state_per_frame_and_queues_events_in_order),
        cmocka_unit_test(orbit_drag_turns_around_the_target_and_scroll_zooms),
        cmocka_unit_test(fly_mode_moves_with_wasd_and_looks_with_the_right_button),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
