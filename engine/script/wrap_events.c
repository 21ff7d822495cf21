// on_contact and on_splash: what the step just taken did to the script's bodies, called after
// the step and before on_step (scr_fire_events), and their thresholds
// (seiche.set_contact_threshold, seiche.set_splash_threshold).
//
// Contacts. The coupling steps Bullet once per fluid substep, so a hit may fall in any of a
// frame's substeps: the Bullet world sums each body pair's contact impulses over the frame
// (phys_world_set_contact_sums, turned on by eng_script_set_host). A pair whose frame impulse
// passes the threshold calls on_contact once, then not again until its frame impulse has
// fallen to half the threshold or below (it stopped touching, or rests more lightly): a crate
// that lands and then lies there is one hit, a ball that bounces is one per bounce.
//
// Splashes. The fluid measures its force on every two-way body in each step, and the
// coupling reads that back a step later through a fence (docs/coupling.md: no stall beyond
// what the coupling already waits for): cpl_body_stats holds the force and the number of
// particle contacts of the step it measured. A body is wet in a step when particles touched it
// and the water pushed it up (against gravity); a splash is a wet step after at least
// SPLASH_DRY_STEPS measured steps that were not, at a downward speed (along gravity) at the
// end of that step of at least the splash threshold (the water's push measured in a step acts
// from the next one on, so that is the speed the body met the water with). Spray falling on a body pushes it
// down, so it does not wet it in this sense; a floating body stays wet.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/// Measured fluid steps in a row a body must have been dry before a wet one is a splash.
#define SPLASH_DRY_STEPS 3

// ---- thresholds --------------------------------------------------------------------------------

static int l_set_contact_threshold(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    s->contact_threshold = scr_arg_number(L, 1, "seiche.set_contact_threshold", "impulse", 0, 1e9, 0, "N s");
    return 0;
}

static int l_contact_threshold(lua_State *L)
{
    lua_pushnumber(L, scr_get_script(L)->contact_threshold);
    return 1;
}

static int l_set_splash_threshold(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    s->splash_speed = scr_arg_number(L, 1, "seiche.set_splash_threshold", "speed", 0, MAX_SPEED, 0, "m/s");
    return 0;
}

static int l_splash_threshold(lua_State *L)
{
    lua_pushnumber(L, scr_get_script(L)->splash_speed);
    return 1;
}

// ---- contacts --------------------------------------------------------------------------------

static bool same_id(phys_body_id a, phys_body_id b)
{
    return a.index1 == b.index1 && a.world0 == b.world0 && a.generation == b.generation;
}

// The slot of the script's live body with Bullet id `id`, or NO_SLOT (the container's walls).
static uint32_t body_slot(const eng_script *s, phys_body_id id)
{
    for (uint32_t i = 0; i < s->obj_count; i++) {
        const obj *o = &s->objs[i];
        if (o->state == OBJ_LIVE && o->kind == OBJ_BODY && same_id(o->u.body.id, id)) return i;
    }
    return NO_SLOT;
}

static bool was_hit(const eng_script *s, phys_body_id a, phys_body_id b)
{
    for (uint32_t i = 0; i < s->hit_count; i++)
        if (same_id(s->hits[i].a, a) && same_id(s->hits[i].b, b)) return true;
    return false;
}

typedef struct contact_event {
    uint32_t a, a_gen, b, b_gen; // slots (b NO_SLOT: the container)
    double impulse, point[3], normal[3];
} contact_event;

static eng_script_status fire_contacts(eng_script *s)
{
    if (!s->contacts && !(s->contacts = malloc(SCR_MAX_CONTACTS * sizeof *s->contacts))) return ENG_SCRIPT_OK;
    if (!s->hits && !(s->hits = malloc(SCR_MAX_CONTACTS * sizeof *s->hits))) return ENG_SCRIPT_OK;
    s->hit_cap = SCR_MAX_CONTACTS;
    int n = 0;
    if (phys_world_take_contact_sums(s->host.phys, 0.0f, s->contacts, SCR_MAX_CONTACTS, &n) != PHYS_OK) return ENG_SCRIPT_OK;
    if (n > SCR_MAX_CONTACTS) {
        eng_log(&s->log, ENG_LOG_WARN, "%s: %d body pairs touched in one frame; on_contact looked at the first %d", s->path,
                n, SCR_MAX_CONTACTS);
        n = SCR_MAX_CONTACTS;
    }
    // Which pairs hit now, and which stay marked as having hit (no new call until they drop to
    // half the threshold): decided for all before any callback runs.
    contact_event *events = n ? malloc((size_t)n * sizeof *events) : NULL;
    int count = 0;
    uint32_t kept = 0;
    scr_hit_pair *next = n ? malloc((size_t)n * sizeof *next) : NULL;
    if (n && (!events || !next)) {
        free(events);
        free(next);
        return ENG_SCRIPT_OK;
    }
    for (int i = 0; i < n; i++) {
        const phys_contact *c = &s->contacts[i];
        bool hit_before = was_hit(s, c->a, c->b);
        bool hits = !hit_before && c->impulse > s->contact_threshold;
        if ((hit_before || hits) && c->impulse > 0.5 * s->contact_threshold) next[kept++] = (scr_hit_pair){ c->a, c->b };
        if (!hits) continue;
        uint32_t a = body_slot(s, c->a), b = body_slot(s, c->b);
        if (a == NO_SLOT && b == NO_SLOT) continue;
        // a: the script's body, and the dynamic one when only one is; the normal still points
        // from a to b.
        double sign = 1.0;
        if (a == NO_SLOT || (b != NO_SLOT && s->objs[a].u.body.def.type != PHYS_BODY_DYNAMIC &&
                             s->objs[b].u.body.def.type == PHYS_BODY_DYNAMIC)) {
            uint32_t t = a;
            a = b;
            b = t;
            sign = -1.0;
        }
        contact_event *e = &events[count++];
        e->a = a;
        e->a_gen = s->objs[a].generation;
        e->b = b;
        e->b_gen = b == NO_SLOT ? 0 : s->objs[b].generation;
        e->impulse = c->impulse;
        e->point[0] = c->point.x, e->point[1] = c->point.y, e->point[2] = c->point.z;
        e->normal[0] = sign * c->normal.x, e->normal[1] = sign * c->normal.y, e->normal[2] = sign * c->normal.z;
    }
    if (kept) memcpy(s->hits, next, kept * sizeof *next); // next is NULL when no pair touched
    s->hit_count = kept;
    free(next);
    eng_script_status st = ENG_SCRIPT_OK;
    for (int i = 0; i < count && st == ENG_SCRIPT_OK; i++) {
        const contact_event *e = &events[i];
        // An earlier callback of this frame may have destroyed one of the bodies.
        if (!scr_obj_at(s, e->a, e->a_gen) || (e->b != NO_SLOT && !scr_obj_at(s, e->b, e->b_gen))) continue;
        scr_arg args[5] = { { .type = 'h', .slot = e->a }, { .type = 'h', .slot = e->b },
                            { .type = 'n', .number = e->impulse },
                            { .type = 'v', .vec = { e->point[0], e->point[1], e->point[2] } },
                            { .type = 'v', .vec = { e->normal[0], e->normal[1], e->normal[2] } } };
        st = scr_callback(s, "on_contact", 5, args);
    }
    free(events);
    return st;
}

// ---- splashes --------------------------------------------------------------------------------

typedef struct splash_event {
    uint32_t slot, gen;
    double speed, volume;
} splash_event;

// Looks at the latest fluid measurement of a body: true (and the event) when it is a splash.
static bool splash_of(eng_script *s, uint32_t slot, const float down[3], uint64_t now, splash_event *out)
{
    obj *o = &s->objs[slot];
    body_rec *b = &o->u.body;
    cpl_body_stats st;
    bool found = false;
    if (cpl_body_get_stats(s->host.coupling, b->id, &st) == CPL_OK && st.two_way &&
        !(b->splash_seen && st.force_step == b->splash_step)) {
        b->splash_seen = true;
        b->splash_step = st.force_step;
        double lift = -(st.force[0] * down[0] + st.force[1] * down[1] + st.force[2] * down[2]);
        bool wet = st.contacts > 0 && lift > 0.0;
        if (wet && b->dry_steps >= SPLASH_DRY_STEPS) {
            // The velocity at the end of the measured step, when remembered (else now's): the
            // water's force of that step acts from the next step on, so it is the speed the
            // body met the water with.
            float v[3];
            uint32_t k = (uint32_t)((st.force_step + 1) % SCR_VELOCITY_HISTORY);
            if (b->step_index[k] == st.force_step + 2) memcpy(v, b->step_velocity[k], sizeof v);
            else scr_body_state(s, o, NULL, NULL, v, NULL);
            double speed = v[0] * down[0] + v[1] * down[1] + v[2] * down[2];
            float volume = 0.0f;
            phys_shape_get_volume(s->host.phys, b->shape_id, &volume);
            if (speed >= s->splash_speed) {
                *out = (splash_event){ slot, o->generation, speed, volume };
                found = true;
            }
        }
        b->dry_steps = wet ? 0 : b->dry_steps < UINT32_MAX ? b->dry_steps + 1 : b->dry_steps;
    }
    // The velocity now is the velocity at the start of the next step.
    uint32_t k = (uint32_t)(now % SCR_VELOCITY_HISTORY);
    scr_body_state(s, o, NULL, NULL, b->step_velocity[k], NULL);
    b->step_index[k] = now + 1;
    return found;
}

static eng_script_status fire_splashes(eng_script *s)
{
    if (!s->host.coupling) return ENG_SCRIPT_OK;
    phys_vec3 g = phys_world_get_gravity(s->host.phys);
    double len = sqrt((double)g.x * g.x + (double)g.y * g.y + (double)g.z * g.z);
    float down[3] = { 0.0f, -1.0f, 0.0f }; // without gravity, "down" is -y
    if (len > 0.0) down[0] = (float)(g.x / len), down[1] = (float)(g.y / len), down[2] = (float)(g.z / len);
    uint64_t now = cpl_step_count(s->host.coupling);
    splash_event events[64];
    int count = 0;
    for (uint32_t i = 0; i < s->obj_count && count < 64; i++) {
        obj *o = &s->objs[i];
        if (o->state != OBJ_LIVE || o->kind != OBJ_BODY || o->u.body.def.type != PHYS_BODY_DYNAMIC) continue;
        if (!cpl_has_body(s->host.coupling, o->u.body.id)) continue;
        if (splash_of(s, i, down, now, &events[count])) count++;
    }
    eng_script_status st = ENG_SCRIPT_OK;
    for (int i = 0; i < count && st == ENG_SCRIPT_OK; i++) {
        if (!scr_obj_at(s, events[i].slot, events[i].gen)) continue; // destroyed by an earlier callback
        scr_arg args[3] = { { .type = 'h', .slot = events[i].slot }, { .type = 'n', .number = events[i].speed },
                            { .type = 'n', .number = events[i].volume } };
        st = scr_callback(s, "on_splash", 3, args);
    }
    return st;
}

eng_script_status scr_fire_events(eng_script *s)
{
    if (!s->host.phys) return ENG_SCRIPT_OK;
    eng_script_status st = fire_contacts(s);
    return st == ENG_SCRIPT_OK ? fire_splashes(s) : st;
}

static const luaL_Reg functions[] = {
    { "set_contact_threshold", l_set_contact_threshold }, { "contact_threshold", l_contact_threshold },
    { "set_splash_threshold", l_set_splash_threshold }, { "splash_threshold", l_splash_threshold },
    { NULL, NULL },
};

void scr_open_events(scr_api *api) { scr_api_functions(api, functions); }
