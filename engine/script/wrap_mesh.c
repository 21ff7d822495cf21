// Meshes from files in scenes (docs/meshes.md): the fields a mesh file is named and placed by
// (mesh, scale, centre, hull_points; seiche.body{mesh = ...} reads them through here), and
// seiche.fill, which fills a closed mesh's inside with water.
//
// Files are found as scr_scene_file says (relative to the file that names them, inside the
// scene's folder unless --trusted) and read when the call is made, so a missing or broken
// file is an error at that line; the Bullet shape (a hull for dynamic bodies, the triangles for
// the others) and the fill's lattice, which need the world, are made when the edit is applied.
#include "engine/script/script_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const CENTRES[3] = { "origin", "bounds", "base" }; // = eng_mesh_centre

bool scr_read_mesh_fields(lua_State *L, eng_script *s, int t, const char *fn, bool hull_points_allowed,
                          scr_mesh_request *out)
{
    memset(out, 0, sizeof *out);
    out->options = eng_default_mesh_file_options();
    out->hull_points = ENG_MESH_HULL_DEFAULT_POINTS;
    static const char *const options[] = { "scale", "centre", "hull_points" };
    if (!scr_field_present(L, t, "mesh")) {
        for (int k = 0; k < 3; k++)
            if (scr_field_present(L, t, options[k]))
                scr_raise(L, "%s: field '%s' applies to meshes from files only (give mesh = \"file.obj\")", fn, options[k]);
        return false;
    }
    char got[64];
    if (lua_type(L, -1) != LUA_TSTRING)
        scr_raise(L, "%s: field 'mesh' must be a file name, e.g. \"assets/boat.obj\" (got %s)", fn,
                  scr_describe(L, -1, got, sizeof got));
    const char *rel = lua_tostring(L, -1);
    snprintf(out->name, sizeof out->name, "%s", rel);
    const char *why = scr_scene_file(L, s, rel, out->path, sizeof out->path);
    if (why) // scr_scene_file's reasons are phrases ("missing", "a path through '..'"): made a sentence
        scr_raise(L, "%s: field 'mesh': \"%.200s\" %s%s (mesh files are found from the folder of the script that names "
                  "them, in the scene's folder or below; docs/lua-api.md, seiche.body)", fn, rel,
                  strcmp(why, "missing") == 0      ? "does not exist"
                  : strcmp(why, "unreadable") == 0 ? "cannot be read"
                  : strncmp(why, "outside", 7) == 0 ? "lies "
                                                    : "is ",
                  strcmp(why, "missing") == 0 || strcmp(why, "unreadable") == 0 ? "" : why);
    if (!s->trusted) { // the file and what it names (a .gltf's buffers) stay in the scene's folder
        scr_scene_root(s, out->root, sizeof out->root);
        out->options.root = out->root;
    }
    // The importer runs apart: it ends with the call's budget, and a call whose budget is spent
    // (the hook looks at the clock only every so many instructions) stops here, not after the
    // importer's own 30 s (a fuzzed script's 13 loads in a row ran 24.9 s past a 0.25 s budget).
    scr_check_now(L, s);
    double left = scr_budget_left(s);
    if (left > 0.0 && left < out->options.timeout_s) out->options.timeout_s = left > 1e-3 ? left : 1e-3;
    lua_pop(L, 1);
    double v;
    if (scr_opt_number(L, t, fn, "scale", 0, 1e6, OPEN_LO, "(metres per file unit)", &v)) out->options.scale = (float)v;
    int c = scr_opt_enum(L, t, fn, "centre", CENTRES, 3);
    if (c >= 0) out->options.centre = (eng_mesh_centre)c;
    if (scr_field_present(L, t, "hull_points")) {
        lua_pop(L, 1);
        if (!hull_points_allowed)
            scr_raise(L, "%s: field 'hull_points' applies to dynamic bodies (their shape is the mesh's convex hull)", fn);
        out->has_hull_points = true;
        out->hull_points = (uint32_t)scr_req_number(L, t, fn, "hull_points", ENG_MESH_HULL_MIN_POINTS,
                                                    ENG_MESH_HULL_MAX_POINTS, WHOLE, "(points)");
    }
    return true;
}

bool scr_load_mesh(const scr_mesh_request *r, eng_mesh_data **out, char *err, size_t size)
{
    *out = calloc(1, sizeof **out);
    if (!*out) {
        snprintf(err, size, "out of memory");
        return false;
    }
    if (!eng_mesh_file_load(r->path, &r->options, *out, err, size)) {
        free(*out);
        *out = NULL;
        return false;
    }
    snprintf((*out)->name, sizeof (*out)->name, "%s", r->name); // messages name it as the script did
    return true;
}

size_t scr_mesh_bytes(const eng_mesh_data *m)
{
    return m ? sizeof *m + (size_t)m->vertex_count * 3 * sizeof(float) + (size_t)m->triangle_count * 3 * sizeof(uint32_t)
             : 0;
}

void scr_free_mesh(eng_mesh_data *m)
{
    eng_mesh_data_free(m);
    free(m);
}

// ---- seiche.fill ---------------------------------------------------------------------------------

static const char *const FILL_FIELDS[] = { "mesh", "scale", "centre", "position", "rotation", "velocity", "clearance",
                                           NULL };

static int l_fill(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.fill";
    scr_check_table_arg(L, 1, fn, "mesh = \"file.obj\", position = {x, y, z}, rotation = ..., velocity = {x, y, z}, ...");
    scr_check_fields(L, 1, fn, FILL_FIELDS);
    scr_mesh_request r;
    if (!scr_read_mesh_fields(L, s, 1, fn, false, &r))
        scr_raise(L, "%s: field 'mesh' is required: the file of a closed mesh whose inside to fill, e.g. \"assets/pool.obj\" "
                  "(got nil)", fn);
    float pos[3] = { 0, 0, 0 }, rot[4] = { 0, 0, 0, 1 }, vel[3] = { 0, 0, 0 };
    scr_opt_position(L, 1, fn, "position", pos);
    scr_opt_rotation(L, 1, fn, "rotation", rot);
    scr_opt_vec(L, 1, fn, "velocity", 3, -MAX_SPEED, MAX_SPEED, 0, "m/s", vel);
    double clearance = 0.0;
    scr_opt_number(L, 1, fn, "clearance", 0, 1000, 0, "m", &clearance);
    command *c = scr_push_command(L, s, CMD_FILL, fn);
    char err[768];
    eng_mesh_data *m = NULL;
    if (!scr_load_mesh(&r, &m, err, sizeof err)) {
        s->command_count--;
        scr_check_now(L, s); // an importer the budget's end stopped: the budget is the reason
        scr_raise(L, "%s: %s", fn, err);
    }
    if (m->open_edges) {
        uint32_t open = m->open_edges;
        scr_free_mesh(m);
        s->command_count--;
        scr_raise(L, "%s: mesh '%s' has %u open edges (edges of one triangle only: holes): it has no inside to fill "
                  "(close it, e.g. cap its holes)", fn, r.name, open);
    }
    size_t bytes = scr_mesh_bytes(m);
    if (bytes > scr_memory_room(s)) {
        scr_free_mesh(m);
        s->command_count--;
        scr_charge(L, s, fn, bytes); // raises with the numbers
    }
    s->c_memory += bytes; // given back when the command is freed
    c->u.fill.mesh = m;
    memcpy(c->u.fill.pos, pos, sizeof pos);
    memcpy(c->u.fill.rot, rot, sizeof rot);
    memcpy(c->u.fill.vel, vel, sizeof vel);
    c->u.fill.clearance = (float)clearance;
    return 0;
}

eng_script_status scr_apply_fill(eng_script *s, const command *c)
{
    pbf_world *fw = s->host.world;
    const pbf_params *p = pbf_world_params(fw);
    uint32_t capacity = pbf_world_capacity(fw), used = pbf_world_particle_count(fw);
    eng_mesh_fill_options o = eng_default_mesh_fill_options();
    o.clearance = c->u.fill.clearance;
    o.max_points = capacity > used ? capacity - used : 1;
    memcpy(o.position, c->u.fill.pos, sizeof o.position);
    memcpy(o.rotation, c->u.fill.rot, sizeof o.rotation);
    float *xyz = NULL;
    uint32_t n = 0;
    char err[768];
    if (!eng_mesh_fill_points(c->u.fill.mesh, 2.0f * p->particle_radius, &o, &xyz, &n, err, sizeof err))
        return scr_refuse(s, c, "%s%s", err, capacity <= used ? " (the fluid is full)" : "");
    if (n == 0) {
        free(xyz);
        return scr_refuse(s, c, "mesh '%s' holds no site of the particle lattice (spacing %g m) inside it: it is too "
                          "small or thin for this particle_radius", c->u.fill.mesh->name, 2.0 * p->particle_radius);
    }
    float *vel = NULL;
    bool moving = c->u.fill.vel[0] != 0.0f || c->u.fill.vel[1] != 0.0f || c->u.fill.vel[2] != 0.0f;
    if (moving && !(vel = malloc((size_t)n * 3 * sizeof *vel))) {
        free(xyz);
        return scr_refuse(s, c, "out of memory");
    }
    for (uint32_t i = 0; vel && i < n; i++) memcpy(vel + 3 * i, c->u.fill.vel, 3 * sizeof(float));
    pbf_result r = pbf_world_add_particles(fw, xyz, vel, n);
    free(xyz);
    free(vel);
    return r == PBF_OK ? ENG_SCRIPT_OK : scr_refuse(s, c, "%s", pbf_world_last_error(fw));
}

static const luaL_Reg functions[] = { { "fill", l_fill }, { NULL, NULL } };

void scr_open_mesh(scr_api *api) { scr_api_functions(api, functions); }
