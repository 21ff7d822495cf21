// The queues the bindings fill: world edits (commands), queued by scr_push_command and carried
// out in order by eng_script_apply between steps; injected input, delivered at a frame's start.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---- commands ---------------------------------------------------------------------------

command *scr_push_command(lua_State *L, eng_script *s, cmd_type type, const char *fn)
{
    if (s->command_count == s->command_cap) {
        int cap = s->command_cap ? 2 * s->command_cap : 32;
        if (cap > (1 << 22)) scr_raise(L, "%s: more than %d edits queued in one frame", fn, 1 << 22);
        // The queue counts against the script's memory limit (4M edits would be 1.2 GB).
        size_t more = (size_t)(cap - s->command_cap) * sizeof(command);
        scr_charge(L, s, fn, more);
        command *c = realloc(s->commands, (size_t)cap * sizeof *c);
        if (!c) {
            scr_uncharge(s, more);
            scr_raise(L, "%s: out of memory", fn);
        }
        s->commands = c;
        s->command_cap = cap;
    }
    command *c = &s->commands[s->command_count++];
    memset(c, 0, sizeof *c);
    c->type = type;
    c->fn = fn;
    scr_where(L, c->where, sizeof c->where);
    return c;
}

static void free_command(eng_script *s, command *c)
{
    if (c->type == CMD_FILL && c->u.fill.mesh) {
        scr_uncharge(s, scr_mesh_bytes(c->u.fill.mesh));
        scr_free_mesh(c->u.fill.mesh);
        c->u.fill.mesh = NULL;
    }
    if (c->type == CMD_PARTICLES) {
        size_t bytes = (c->u.particles.pos ? 1 : 0) + (c->u.particles.vel ? 1 : 0);
        scr_uncharge(s, bytes * 3 * (size_t)c->u.particles.n * sizeof(float));
        free(c->u.particles.pos);
        free(c->u.particles.vel);
        c->u.particles.pos = c->u.particles.vel = NULL;
    }
}

void scr_clear_commands(eng_script *s)
{
    for (int i = 0; i < s->command_count; i++) free_command(s, &s->commands[i]);
    s->command_count = 0;
}

// ---- applying the queued edits ------------------------------------------------------------

eng_script_status scr_refuse(eng_script *s, const command *c, const char *fmt, ...)
{
    char msg[2048], lua[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    // Refusals often carry the C API's message: the script reads its own names.
    snprintf(s->error, sizeof s->error, "%s%s: %s", c->where, c->fn, scr_lua_wording(msg, lua, sizeof lua));
    return ENG_SCRIPT_ERROR;
}

// A point the fluid would refuse for lying outside its domain, in the script's words ("field
// 'max'.x must be in [0, 1] m, inside the domain (got 5)"): the bindings check it when the world
// exists, and applying checks it again (an edit queued by the main chunk meets the domain here).
// s->config's domain is the world's once it is built (the app writes it back).
bool scr_domain_check(const eng_script *s, const float p[3], const char *what, char *msg, size_t size)
{
    static const char axis[] = "xyz";
    const eng_scene_config *c = &s->config;
    for (int k = 0; k < 3; k++)
        if (!(p[k] >= c->domain_min[k] && p[k] <= c->domain_max[k])) {
            char a[32], b[32], v[32];
            snprintf(msg, size, "%s.%c must be in [%s, %s] m, inside the domain (got %s)", what, axis[k],
                     scr_fmt_number(c->domain_min[k], a, sizeof a), scr_fmt_number(c->domain_max[k], b, sizeof b),
                     scr_fmt_number(p[k], v, sizeof v));
            return false;
        }
    return true;
}

bool scr_points_domain_check(const eng_script *s, const float *points, uint32_t n, const char *field, char *msg,
                             size_t size)
{
    for (uint32_t i = 0; i < n; i++) {
        char what[96];
        snprintf(what, sizeof what, "field '%s'[%u]", field, i + 1); // Lua counts from 1
        if (!scr_domain_check(s, points + 3 * (size_t)i, what, msg, size)) return false;
    }
    return true;
}

static eng_script_status apply_body_add(eng_script *s, const command *c, obj *o)
{
    body_rec *b = &o->u.body;
    phys_world *w = s->host.phys;
    phys_result r = PHYS_OK;
    float mesh_com[3] = { 0, 0, 0 }; // a file mesh's hull: its centre of mass in the mesh frame
    if (b->file) {
        // A mesh from a file: its convex hull (dynamic) around the hull's centre of mass, then
        // drawn moved by minus that; or its triangles as they are.
        char err[768];
        if (b->def.type == PHYS_BODY_DYNAMIC) {
            eng_mesh_hull h;
            if (!eng_mesh_create_hull(w, b->file, b->hull_points, &h, err, sizeof err)) return scr_refuse(s, c, "%s", err);
            b->shape_id = h.shape;
            memcpy(mesh_com, h.centre_of_mass, sizeof mesh_com);
            float back[3] = { -mesh_com[0], -mesh_com[1], -mesh_com[2] };
            eng_mesh_data_translate(b->file, back);
        } else if (!eng_mesh_create_static_shape(w, b->file, &b->shape_id, err, sizeof err)) {
            return scr_refuse(s, c, "%s", err);
        }
    }
    switch (b->file ? SHAPE_COUNT : b->shape) {
    case SHAPE_BOX: {
        phys_box box = { { b->dims[0], b->dims[1], b->dims[2] } };
        r = phys_shape_create_box(w, &box, &b->shape_id);
        break;
    }
    case SHAPE_SPHERE: {
        phys_sphere sp = { b->dims[0] };
        r = phys_shape_create_sphere(w, &sp, &b->shape_id);
        break;
    }
    case SHAPE_CAPSULE: {
        phys_capsule cp = { b->dims[0], b->dims[1] };
        r = phys_shape_create_capsule(w, &cp, &b->shape_id);
        break;
    }
    case SHAPE_CYLINDER: {
        phys_cylinder cy = { b->dims[0], b->dims[1] };
        r = phys_shape_create_cylinder(w, &cy, &b->shape_id);
        break;
    }
    case SHAPE_PLANE: {
        phys_plane pl = { { b->dims[0], b->dims[1], b->dims[2] }, b->dims[3] };
        r = phys_shape_create_plane(w, &pl, &b->shape_id);
        break;
    }
    case SHAPE_HULL: {
        phys_convex_hull h = { (const phys_vec3 *)b->points, b->point_count };
        r = phys_shape_create_convex_hull(w, &h, &b->shape_id);
        break;
    }
    case SHAPE_MESH: {
        phys_triangle_mesh m = { (const phys_vec3 *)b->points, b->point_count, b->indices, b->index_count / 3 };
        r = phys_shape_create_triangle_mesh(w, &m, &b->shape_id);
        break;
    }
    case SHAPE_COMPOUND: {
        phys_compound_part parts[MAX_BODY_PARTS];
        memset(parts, 0, sizeof parts);
        for (uint32_t i = 0; i < b->part_count; i++) {
            const body_part *bp = &b->parts[i];
            phys_compound_part *pp = &parts[i];
            const float *dm = bp->dims;
            switch (bp->shape) {
            case SHAPE_BOX: pp->type = PHYS_SHAPE_BOX; pp->box.half_extents = (phys_vec3){ dm[0], dm[1], dm[2] }; break;
            case SHAPE_SPHERE: pp->type = PHYS_SHAPE_SPHERE; pp->sphere.radius = dm[0]; break;
            case SHAPE_CAPSULE: pp->type = PHYS_SHAPE_CAPSULE; pp->capsule = (phys_capsule){ dm[0], dm[1] }; break;
            default: pp->type = PHYS_SHAPE_CYLINDER; pp->cylinder = (phys_cylinder){ dm[0], dm[1] }; break;
            }
            pp->position = scr_pv(bp->pos);
            pp->rotation = scr_pq(bp->rot);
        }
        phys_compound cm = { parts, b->part_count };
        r = phys_shape_create_compound(w, &cm, &b->shape_id);
        break;
    }
    default: break;
    }
    if (r != PHYS_OK) return scr_refuse(s, c, "%s", phys_world_last_error(w));
    phys_body_def d = b->def;
    d.shape = b->shape_id;
    if (b->file) { // the script placed the mesh's origin; the body sits at its centre of mass
        float q[4] = { d.orientation.x, d.orientation.y, d.orientation.z, d.orientation.w }, wo[3];
        scr_quat_rotate(q, mesh_com, wo);
        d.position = (phys_vec3){ d.position.x + wo[0], d.position.y + wo[1], d.position.z + wo[2] };
    }
    if (b->shape == SHAPE_COMPOUND) {
        // The script placed the parts' frame; the body's frame sits at the centre of mass,
        // along the principal axes: position P + Q frame_origin, orientation Q frame_rotation.
        phys_shape_desc sd;
        if (phys_shape_get_desc(w, b->shape_id, &sd) == PHYS_OK) {
            float q[4] = { d.orientation.x, d.orientation.y, d.orientation.z, d.orientation.w };
            float o[3] = { sd.compound.frame_origin.x, sd.compound.frame_origin.y, sd.compound.frame_origin.z }, wo[3];
            float fr[4] = { sd.compound.frame_rotation.x, sd.compound.frame_rotation.y, sd.compound.frame_rotation.z,
                            sd.compound.frame_rotation.w }, qb[4];
            scr_quat_rotate(q, o, wo);
            scr_quat_mul(q, fr, qb);
            d.position = (phys_vec3){ d.position.x + wo[0], d.position.y + wo[1], d.position.z + wo[2] };
            d.orientation = scr_pq(qb);
        }
    }
    if (phys_body_create(w, &d, &b->id) != PHYS_OK) {
        eng_script_status st = scr_refuse(s, c, "%s", phys_world_last_error(w));
        phys_shape_destroy(w, b->shape_id);
        return st;
    }
    if (b->has_factors && (phys_body_set_linear_factor(w, b->id, scr_pv(b->linear_factor)) != PHYS_OK ||
                           phys_body_set_angular_factor(w, b->id, scr_pv(b->angular_factor)) != PHYS_OK)) {
        eng_script_status st = scr_refuse(s, c, "%s", phys_world_last_error(w));
        phys_body_destroy(w, b->id);
        phys_shape_destroy(w, b->shape_id);
        return st;
    }
    if (s->host.coupling) {
        cpl_body_def cd = cpl_default_body_def();
        cd.two_way = b->two_way;
        cd.measure_force = b->measure_force;
        cpl_result cr = cpl_add_body(s->host.coupling, b->id, &cd);
        if (cr != CPL_OK) {
            eng_script_status st = scr_refuse(s, c, "%s%s", cpl_last_error(s->host.coupling),
                                          cr == CPL_ERR_CAPACITY ? " (the fluid couples a limited number of bodies at a "
                                                                   "time: destroy one before making another)" : "");
            phys_body_destroy(w, b->id);
            phys_shape_destroy(w, b->shape_id);
            return st;
        }
    }
    o->state = OBJ_LIVE;
    if (s->host.scene && s->host.meshes) {
        b->mesh = scr_body_mesh(s, b);
        eng_node_def nd = eng_default_node_def();
        nd.parent = s->host.root;
        nd.mesh = b->mesh;
        memcpy(nd.color, b->color, sizeof nd.color);
        nd.visible = b->visible;
        float pos[3] = { d.position.x, d.position.y, d.position.z }, rot[4] = { d.orientation.x, d.orientation.y,
                                                                                   d.orientation.z, d.orientation.w };
        scr_body_transform(b, pos, rot, &nd.local);
        b->node = eng_node_create(s->host.scene, &nd);
    }
    return ENG_SCRIPT_OK;
}

static void body_remove_ids(eng_script *s, phys_body_id id, phys_shape_id shape, eng_node_id node, eng_mesh_id mesh)
{
    if (s->host.coupling && cpl_has_body(s->host.coupling, id)) cpl_remove_body(s->host.coupling, id);
    if (s->host.phys && phys_body_is_valid(s->host.phys, id)) phys_body_destroy(s->host.phys, id);
    if (s->host.phys && phys_shape_is_valid(s->host.phys, shape)) phys_shape_destroy(s->host.phys, shape);
    if (s->host.scene && node.index1) eng_node_destroy(s->host.scene, node);
    if (s->host.meshes && mesh.index1) eng_mesh_destroy(s->host.meshes, mesh);
}

// Velocities that take a kinematic body from its pose to (pos, rot) in one step of dt.
static eng_script_status apply_move_to(eng_script *s, const command *c, body_rec *b)
{
    phys_world *w = s->host.phys;
    phys_vec3 p;
    phys_quat q;
    phys_body_get_pose(w, b->id, &p, &q);
    double dt = s->host.dt;
    phys_vec3 v = { (float)((c->u.pose.pos[0] - p.x) / dt), (float)((c->u.pose.pos[1] - p.y) / dt),
                    (float)((c->u.pose.pos[2] - p.z) / dt) };
    // Rotation delta: target * conj(current), as axis * angle, the short way round.
    float inv[4] = { -q.x, -q.y, -q.z, q.w }, dq[4];
    scr_quat_mul(c->u.pose.rot, inv, dq);
    if (dq[3] < 0) for (int k = 0; k < 4; k++) dq[k] = -dq[k];
    double sn = sqrt((double)dq[0] * dq[0] + (double)dq[1] * dq[1] + (double)dq[2] * dq[2]);
    double angle = 2.0 * atan2(sn, dq[3]);
    phys_vec3 om = { 0, 0, 0 };
    if (sn > 1e-9) {
        double k = angle / (sn * dt);
        om = (phys_vec3){ (float)(dq[0] * k), (float)(dq[1] * k), (float)(dq[2] * k) };
    }
    if (phys_body_set_linear_velocity(w, b->id, v) != PHYS_OK || phys_body_set_angular_velocity(w, b->id, om) != PHYS_OK)
        return scr_refuse(s, c, "%s", phys_world_last_error(w));
    b->target_mode = true;
    b->target_step = s->host.frame + 1;
    return ENG_SCRIPT_OK;
}

static eng_script_status apply_one(eng_script *s, const command *c)
{
    pbf_world *fw = s->host.world;
    phys_world *pw = s->host.phys;
    obj *o = c->slot || c->gen ? scr_obj_at(s, c->slot, c->gen) : NULL;
    switch (c->type) {
    case CMD_BLOCK: {
        char msg[256];
        if (!scr_domain_check(s, c->u.block.min, "field 'min'", msg, sizeof msg) ||
            !scr_domain_check(s, c->u.block.max, "field 'max'", msg, sizeof msg))
            return scr_refuse(s, c, "%s", msg);
        if (pbf_world_add_block(fw, &c->u.block, NULL) != PBF_OK) return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        break;
    }
    case CMD_SPHERE: {
        const pbf_params *p = pbf_world_params(fw);
        float sp = 2.0f * p->particle_radius, r = c->u.sphere.radius;
        static const char axis[] = "xyz";
        const eng_scene_config *cf = &s->config;
        for (int k = 0; k < 3; k++)
            if (c->u.sphere.center[k] - r < cf->domain_min[k] || c->u.sphere.center[k] + r > cf->domain_max[k])
                return scr_refuse(s, c, "the sphere's %c range [%g, %g] must lie inside the domain [%g, %g]", axis[k],
                              (double)(c->u.sphere.center[k] - r), (double)(c->u.sphere.center[k] + r),
                              (double)cf->domain_min[k], (double)cf->domain_max[k]);
        int n = (int)floorf(r / sp);
        uint64_t est = (uint64_t)(2 * n + 1) * (uint64_t)(2 * n + 1) * (uint64_t)(2 * n + 1);
        uint32_t room = pbf_world_capacity(fw) - pbf_world_particle_count(fw);
        if (est / 2 > room) // a sphere fills about half its bounding cube
            return scr_refuse(s, c, "the sphere holds about %llu particles but only %u of capacity %u are free",
                          (unsigned long long)(est * 0.5236), room, pbf_world_capacity(fw));
        float *pos = malloc((size_t)est * 3 * sizeof(float) + 4), *vel = malloc((size_t)est * 3 * sizeof(float) + 4);
        if (!pos || !vel) {
            free(pos);
            free(vel);
            return scr_refuse(s, c, "out of memory");
        }
        uint32_t m = 0;
        for (int z = -n; z <= n; z++)
            for (int y = -n; y <= n; y++)
                for (int x = -n; x <= n; x++) {
                    float d[3] = { (float)x * sp, (float)y * sp, (float)z * sp };
                    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > r * r) continue;
                    for (int k = 0; k < 3; k++) {
                        pos[3 * m + k] = c->u.sphere.center[k] + d[k];
                        vel[3 * m + k] = c->u.sphere.velocity[k];
                    }
                    m++;
                }
        pbf_result pr = pbf_world_add_particles(fw, pos, vel, m);
        free(pos);
        free(vel);
        if (pr != PBF_OK) return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        break;
    }
    case CMD_PARTICLES: {
        char msg[256];
        if (!scr_points_domain_check(s, c->u.particles.pos, c->u.particles.n, "positions", msg, sizeof msg))
            return scr_refuse(s, c, "%s", msg);
        if (c->u.particles.n &&
            pbf_world_add_particles(fw, c->u.particles.pos, c->u.particles.vel, c->u.particles.n) != PBF_OK)
            return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        break;
    }
    case CMD_EMITTER_ADD:
    case CMD_EMITTER_SET: {
        if (!o) break; // removed before it was applied
        pbf_emitter_def full = c->u.emitter;
        const pbf_emitter_def *d = &full;
        float max_rate = pbf_emitter_max_rate(fw, d->speed, d->radius);
        if (c->full_rate) full.rate = max_rate;
        char msg[256], got[32];
        if (!scr_domain_check(s, d->position, "field 'position'", msg, sizeof msg)) return scr_refuse(s, c, "%s", msg);
        if (d->rate > max_rate * 1.0001f) // worded as the binding's own check (wrap_emitter.c)
            return scr_refuse(s, c, "field 'rate' must be a number in [0, %g] particles/s (got %s); %g is the most a nozzle "
                          "of radius %g m pours at speed %g m/s: raise speed or radius for more", (double)max_rate,
                          scr_fmt_number(d->rate, got, sizeof got), (double)max_rate, (double)d->radius, (double)d->speed);
        pbf_result r = c->type == CMD_EMITTER_ADD ? pbf_world_add_emitter(fw, d, &o->u.emitter.id)
                                                  : pbf_world_set_emitter(fw, o->u.emitter.id, d);
        if (r == PBF_OK) r = pbf_world_set_emitter_tint(fw, o->u.emitter.id, c->tinted ? c->tint : NULL);
        if (r != PBF_OK) return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        o->state = OBJ_LIVE;
        break;
    }
    case CMD_TINT:
        if (pbf_world_tint_box(fw, c->u.block.min, c->u.block.max, c->tinted ? c->tint : NULL) != PBF_OK)
            return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        break;
    case CMD_EMITTER_REMOVE:
        if (pbf_emitter_is_valid(fw, c->u.emitter_id)) pbf_world_remove_emitter(fw, c->u.emitter_id);
        break;
    case CMD_SINK_ADD:
        if (!o) break;
        if (pbf_world_add_sink(fw, o->u.sink.min, o->u.sink.max, &o->u.sink.id) != PBF_OK)
            return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        o->state = OBJ_LIVE;
        break;
    case CMD_SINK_REMOVE:
        if (pbf_sink_is_valid(fw, c->u.sink_id)) pbf_world_remove_sink(fw, c->u.sink_id);
        break;
    case CMD_BODY_ADD:
        if (!o) break;
        return apply_body_add(s, c, o);
    case CMD_BODY_REMOVE:
        body_remove_ids(s, c->u.body.id, c->u.body.shape, c->u.body.node, c->u.body.mesh);
        break;
    case CMD_BODY_FORCE:
    case CMD_BODY_TORQUE: {
        if (!o || o->state != OBJ_LIVE) break;
        body_rec *b = &o->u.body;
        const float *v = c->u.vec.v;
        float *h = b->held;
        if (c->type == CMD_BODY_TORQUE) {
            for (int k = 0; k < 3; k++) h[3 + k] += v[k];
        } else {
            for (int k = 0; k < 3; k++) h[k] += v[k];
            phys_vec3 at;
            if (c->u.vec.at_point && phys_body_get_pose(pw, b->id, &at, NULL) == PHYS_OK) {
                float r[3] = { c->u.vec.p[0] - at.x, c->u.vec.p[1] - at.y, c->u.vec.p[2] - at.z };
                h[3] += r[1] * v[2] - r[2] * v[1];
                h[4] += r[2] * v[0] - r[0] * v[2];
                h[5] += r[0] * v[1] - r[1] * v[0];
            }
        }
        b->held_on = true;
        phys_vec3 force = { h[0], h[1], h[2] }, torque = { h[3], h[4], h[5] };
        if (phys_body_set_held_force(pw, b->id, force, torque) != PHYS_OK)
            return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        break;
    }
    case CMD_BODY_IMPULSE:
    case CMD_BODY_ANGULAR_IMPULSE:
    case CMD_BODY_VELOCITY:
    case CMD_BODY_ANGULAR_VELOCITY: {
        if (!o || o->state != OBJ_LIVE) break;
        body_rec *b = &o->u.body;
        phys_vec3 v = scr_pv(c->u.vec.v);
        phys_result r;
        if (c->type == CMD_BODY_IMPULSE)
            r = c->u.vec.at_point ? phys_body_apply_impulse_at_point(pw, b->id, v, scr_pv(c->u.vec.p), true)
                                  : phys_body_apply_impulse(pw, b->id, v, true);
        else if (c->type == CMD_BODY_ANGULAR_IMPULSE) r = phys_body_apply_angular_impulse(pw, b->id, v, true);
        else if (c->type == CMD_BODY_VELOCITY) r = phys_body_set_linear_velocity(pw, b->id, v);
        else r = phys_body_set_angular_velocity(pw, b->id, v);
        if (r != PHYS_OK) return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        if (c->type == CMD_BODY_VELOCITY || c->type == CMD_BODY_ANGULAR_VELOCITY) b->target_mode = false;
        break;
    }
    case CMD_BODY_MOVE_TO:
        if (!o || o->state != OBJ_LIVE) break;
        return apply_move_to(s, c, &o->u.body);
    case CMD_BODY_TELEPORT: {
        if (!o || o->state != OBJ_LIVE) break;
        body_rec *b = &o->u.body;
        phys_vec3 p = scr_pv(c->u.pose.pos);
        phys_quat q = scr_pq(c->u.pose.rot);
        if (s->host.coupling && cpl_has_body(s->host.coupling, b->id)) {
            if (cpl_teleport_body(s->host.coupling, b->id, p, q) != CPL_OK)
                return scr_refuse(s, c, "%s", cpl_last_error(s->host.coupling));
        } else if (phys_body_set_pose(pw, b->id, p, q) != PHYS_OK) {
            return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        }
        b->target_mode = false;
        break;
    }
    case CMD_BODY_LOOK:
        if (!o || !o->u.body.node.index1 || !s->host.scene) break;
        eng_node_set_color(s->host.scene, o->u.body.node, o->u.body.color);
        eng_node_set_visible(s->host.scene, o->u.body.node, o->u.body.visible);
        break;
    case CMD_GRAB_ADD: {
        if (!o) break;
        obj *b = scr_obj_at(s, o->u.grab.body, o->u.grab.body_gen);
        if (!b || b->state != OBJ_LIVE) break;
        phys_point_constraint_def d = phys_default_point_constraint_def();
        d.body = b->u.body.id;
        d.pivot = scr_pv(o->u.grab.pivot);
        if (o->u.grab.max_force > 0) d.max_force = o->u.grab.max_force;
        if (phys_point_constraint_create(pw, &d, &o->u.grab.id) != PHYS_OK)
            return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        o->state = OBJ_LIVE;
        break;
    }
    case CMD_GRAB_MOVE:
        if (!o || o->state != OBJ_LIVE || !phys_constraint_is_valid(pw, o->u.grab.id)) break;
        if (phys_point_constraint_set_pivot(pw, o->u.grab.id, scr_pv(c->u.vec.v)) != PHYS_OK)
            return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        break;
    case CMD_GRAB_REMOVE: {
        if (!phys_constraint_is_valid(pw, c->u.release.id)) break; // never applied, or gone with its body
        phys_constraint_destroy(pw, c->u.release.id);
        obj *b = scr_obj_at(s, c->u.release.body, c->u.release.body_gen);
        if (c->u.release.thrown && b && b->state == OBJ_LIVE &&
            phys_body_set_linear_velocity(pw, b->u.body.id, scr_pv(c->u.release.velocity)) != PHYS_OK)
            return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        break;
    }
    case CMD_JOINT_ADD:
    case CMD_JOINT_MOTOR:
    case CMD_JOINT_LIMITS:
    case CMD_JOINT_REMOVE: return scr_apply_joint(s, c);
    case CMD_FILL: return scr_apply_fill(s, c);
    case CMD_PARAMS:
        if (pbf_world_set_params(fw, &c->u.params) != PBF_OK) return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        break;
    case CMD_GRAVITY: {
        pbf_params p = *pbf_world_params(fw);
        memcpy(p.gravity, c->u.gravity, sizeof p.gravity);
        if (pbf_world_set_params(fw, &p) != PBF_OK) return scr_refuse(s, c, "%s", pbf_world_last_error(fw));
        if (pw && phys_world_set_gravity(pw, scr_pv(c->u.gravity)) != PHYS_OK) return scr_refuse(s, c, "%s", phys_world_last_error(pw));
        break;
    }
    case CMD_CAMERA: {
        eng_camera *cam = s->host.camera;
        if (!cam) break;
        float eye[3], target[3];
        memcpy(eye, c->u.camera.has_eye ? c->u.camera.eye : cam->position, sizeof eye);
        memcpy(target, c->u.camera.has_target ? c->u.camera.target : cam->target, sizeof target);
        if (eye[0] == target[0] && eye[1] == target[1] && eye[2] == target[2])
            return scr_refuse(s, c, "eye and target must differ (both at {%g, %g, %g})", (double)eye[0], (double)eye[1],
                          (double)eye[2]);
        if (c->u.camera.has_mode) eng_camera_set_mode(cam, (eng_camera_mode)c->u.camera.mode);
        if (c->u.camera.has_eye || c->u.camera.has_target) eng_camera_look_at(cam, eye, target);
        if (c->u.camera.has_fov) cam->fov_y = (float)(c->u.camera.fov * PI / 180.0);
        break;
    }
    }
    return ENG_SCRIPT_OK;
}

eng_script_status eng_script_apply(eng_script *s)
{
    if (!s->host.world) return ENG_SCRIPT_OK;
    eng_script_status st = ENG_SCRIPT_OK;
    // In order; applying runs no Lua, so the queue cannot grow meanwhile.
    for (int i = 0; i < s->command_count && st == ENG_SCRIPT_OK; i++) st = apply_one(s, &s->commands[i]);
    scr_clear_commands(s);
    s->have_pending_params = false;
    if (s->command_cap > 4096) { // give back the memory of a burst
        scr_uncharge(s, (size_t)s->command_cap * sizeof(command));
        free(s->commands);
        s->commands = NULL;
        s->command_cap = 0;
    }
    // Kinematic bodies whose target was not renewed for the coming step stop where they are.
    for (uint32_t i = 0; i < s->obj_count && s->host.phys; i++) {
        obj *o = &s->objs[i];
        if (o->state != OBJ_LIVE || o->kind != OBJ_BODY || !o->u.body.target_mode) continue;
        if (o->u.body.target_step == s->host.frame + 1) continue;
        phys_vec3 zero = { 0, 0, 0 };
        phys_body_set_linear_velocity(s->host.phys, o->u.body.id, zero);
        phys_body_set_angular_velocity(s->host.phys, o->u.body.id, zero);
        o->u.body.target_mode = false;
    }
    s->cache_valid = false;
    return st;
}

void eng_script_step_taken(eng_script *s)
{
    for (uint32_t i = 0; i < s->obj_count && s->host.phys; i++) {
        obj *o = &s->objs[i];
        if (o->state != OBJ_LIVE || o->kind != OBJ_BODY || !o->u.body.held_on) continue;
        phys_vec3 zero = { 0, 0, 0 };
        phys_body_set_held_force(s->host.phys, o->u.body.id, zero, zero);
        memset(o->u.body.held, 0, sizeof o->u.body.held);
        o->u.body.held_on = false;
    }
}

// ---- injected input ------------------------------------------------------------------------

void eng_script_deliver_input(eng_script *s)
{
    // A frame begins: loading is over, and the frame's calls get a fresh budget.
    s->loaded = true;
    s->frame_used = 0.0;
    for (int i = 0; i < s->event_count && s->host.input; i++) eng_input_inject(s->host.input, &s->events[i]);
    s->event_count = 0;
}
