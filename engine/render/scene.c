// The scene graph. See scene.h.
#include "engine/render/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct node {
    eng_transform local;
    mat4 world;
    eng_mesh_id mesh;
    float color[3];
    uint32_t generation;
    int parent, first_child, next_sibling, prev_sibling; ///< slot indices, -1 = none
    int next_free;
    bool live, visible, dirty;
} node;

struct eng_scene {
    eng_scene_def def;
    node *nodes;
    int count, cap; ///< slots in use (live or free) and allocated
    int free_head;
    int live;
};

eng_transform eng_identity_transform(void)
{
    eng_transform t = { { 0.0f, 0.0f, 0.0f }, { 0.0f, 0.0f, 0.0f, 1.0f }, { 1.0f, 1.0f, 1.0f } };
    return t;
}

eng_scene_def eng_default_scene_def(void)
{
    eng_scene_def d;
    memset(&d, 0, sizeof d);
    d.max_nodes = 65536;
    d.logger = eng_default_logger();
    return d;
}

eng_node_def eng_default_node_def(void)
{
    eng_node_def d;
    memset(&d, 0, sizeof d);
    d.parent = ENG_NULL_NODE;
    d.local = eng_identity_transform();
    d.mesh = ENG_NULL_MESH;
    d.color[0] = d.color[1] = d.color[2] = 0.8f;
    d.visible = true;
    return d;
}

eng_scene *eng_scene_create(const eng_scene_def *def)
{
    if (def->max_nodes < 1 || def->max_nodes > 1048576) {
        eng_log(&def->logger, ENG_LOG_ERROR, "eng_scene_def.max_nodes must be 1..1048576 (got %d)", def->max_nodes);
        return NULL;
    }
    eng_scene *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->def = *def;
    s->free_head = -1;
    return s;
}

void eng_scene_destroy(eng_scene *scene)
{
    if (!scene) return;
    free(scene->nodes);
    free(scene);
}

int eng_scene_node_count(const eng_scene *scene) { return scene->live; }

static node *get(const eng_scene *s, eng_node_id id)
{
    if (!s || id.index1 == 0 || id.index1 > (uint32_t)s->count) return NULL;
    node *n = &s->nodes[id.index1 - 1];
    return n->live && n->generation == id.generation ? n : NULL;
}

// Like get(), but a stale or null id is reported as a misuse by `fn`.
static node *use(const eng_scene *s, eng_node_id id, const char *fn)
{
    node *n = get(s, id);
    if (!n) {
        if (id.index1 == 0)
            eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: attempt to use a null node id", fn);
        else
            eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: attempt to use a destroyed node (index %u, generation %u)", fn,
                    (unsigned)(id.index1 - 1), (unsigned)id.generation);
    }
    return n;
}

static int slot_of(const eng_scene *s, const node *n) { return (int)(n - s->nodes); }

static eng_node_id id_of(const eng_scene *s, int slot)
{
    eng_node_id id = { (uint32_t)slot + 1, s->nodes[slot].generation };
    return id;
}

static bool check_transform(const eng_scene *s, const char *fn, const char *field, const eng_transform *t)
{
    for (int k = 0; k < 3; k++) {
        if (!isfinite(t->translation[k])) {
            eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: %s.translation[%d] must be finite m (got %g)", fn, field, k,
                    (double)t->translation[k]);
            return false;
        }
        if (!isfinite(t->scale[k]) || t->scale[k] == 0.0f) {
            eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: %s.scale[%d] must be finite and non-zero (got %g)", fn, field,
                    k, (double)t->scale[k]);
            return false;
        }
    }
    float len = sqrtf(t->rotation[0] * t->rotation[0] + t->rotation[1] * t->rotation[1] +
                      t->rotation[2] * t->rotation[2] + t->rotation[3] * t->rotation[3]);
    if (!(fabsf(len - 1.0f) <= 1e-3f)) {
        eng_log(&s->def.logger, ENG_LOG_ERROR,
                "%s: %s.rotation must be a unit quaternion (x, y, z, w), length 1 +- 0.001 (got length %g)", fn, field,
                (double)len);
        return false;
    }
    return true;
}

static bool check_color(const eng_scene *s, const char *fn, const char *field, const float c[3])
{
    for (int k = 0; k < 3; k++) {
        if (!(c[k] >= 0.0f && c[k] <= 1.0f)) {
            eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: %s[%d] must be 0..1 (got %g)", fn, field, k, (double)c[k]);
            return false;
        }
    }
    return true;
}

// Marks a node and its subtree for recomputation. A dirty node's subtree is already dirty.
static void mark_dirty(eng_scene *s, int slot)
{
    node *n = &s->nodes[slot];
    if (n->dirty) return;
    n->dirty = true;
    for (int c = n->first_child; c >= 0; c = s->nodes[c].next_sibling) mark_dirty(s, c);
}

static void link_child(eng_scene *s, int parent, int child)
{
    node *c = &s->nodes[child];
    c->parent = parent;
    c->prev_sibling = -1;
    c->next_sibling = -1;
    if (parent < 0) return;
    node *p = &s->nodes[parent];
    c->next_sibling = p->first_child;
    if (p->first_child >= 0) s->nodes[p->first_child].prev_sibling = child;
    p->first_child = child;
}

static void unlink_child(eng_scene *s, int child)
{
    node *c = &s->nodes[child];
    if (c->prev_sibling >= 0) s->nodes[c->prev_sibling].next_sibling = c->next_sibling;
    else if (c->parent >= 0) s->nodes[c->parent].first_child = c->next_sibling;
    if (c->next_sibling >= 0) s->nodes[c->next_sibling].prev_sibling = c->prev_sibling;
    c->parent = c->prev_sibling = c->next_sibling = -1;
}

eng_node_id eng_node_create(eng_scene *scene, const eng_node_def *def)
{
    const char *fn = "eng_node_create";
    int parent = -1;
    if (def->parent.index1 != 0) {
        node *p = get(scene, def->parent);
        if (!p) {
            eng_log(&scene->def.logger, ENG_LOG_ERROR,
                    "%s: eng_node_def.parent must be a live node or ENG_NULL_NODE (got a destroyed node, index %u)", fn,
                    (unsigned)(def->parent.index1 - 1));
            return ENG_NULL_NODE;
        }
        parent = slot_of(scene, p);
    }
    if (!check_transform(scene, fn, "eng_node_def.local", &def->local)) return ENG_NULL_NODE;
    if (!check_color(scene, fn, "eng_node_def.color", def->color)) return ENG_NULL_NODE;
    int slot = scene->free_head;
    if (slot >= 0) {
        scene->free_head = scene->nodes[slot].next_free;
    } else {
        if (scene->count >= scene->def.max_nodes) {
            eng_log(&scene->def.logger, ENG_LOG_ERROR, "%s: the scene is full (eng_scene_def.max_nodes = %d)", fn,
                    scene->def.max_nodes);
            return ENG_NULL_NODE;
        }
        if (scene->count == scene->cap) {
            int cap = scene->cap ? scene->cap * 2 : 64;
            if (cap > scene->def.max_nodes) cap = scene->def.max_nodes;
            node *n = realloc(scene->nodes, (size_t)cap * sizeof *n);
            if (!n) {
                eng_log(&scene->def.logger, ENG_LOG_ERROR, "%s: out of memory", fn);
                return ENG_NULL_NODE;
            }
            scene->nodes = n;
            scene->cap = cap;
        }
        slot = scene->count++;
        scene->nodes[slot].generation = 0;
    }
    node *n = &scene->nodes[slot];
    uint32_t gen = n->generation + 1;
    if (gen == 0) gen = 1; // zero is reserved for null ids
    memset(n, 0, sizeof *n);
    n->generation = gen;
    n->live = true;
    n->local = def->local;
    n->mesh = def->mesh;
    memcpy(n->color, def->color, sizeof n->color);
    n->visible = def->visible;
    n->first_child = -1;
    n->next_free = -1;
    n->dirty = false;
    link_child(scene, parent, slot);
    mark_dirty(scene, slot);
    scene->live++;
    return id_of(scene, slot);
}

static void free_slot(eng_scene *s, int slot)
{
    node *n = &s->nodes[slot];
    n->live = false;
    n->next_free = s->free_head;
    s->free_head = slot;
    s->live--;
}

void eng_node_destroy(eng_scene *scene, eng_node_id id)
{
    node *n = use(scene, id, "eng_node_destroy");
    if (!n) return;
    int root = slot_of(scene, n);
    unlink_child(scene, root);
    // Post-order walk without recursion: go down first children to a leaf, free it (it is
    // its parent's first child), climb back and repeat until the root itself is a leaf.
    int cur = root;
    for (;;) {
        while (scene->nodes[cur].first_child >= 0) cur = scene->nodes[cur].first_child;
        if (cur == root) break;
        int p = scene->nodes[cur].parent;
        scene->nodes[p].first_child = scene->nodes[cur].next_sibling;
        if (scene->nodes[cur].next_sibling >= 0) scene->nodes[scene->nodes[cur].next_sibling].prev_sibling = -1;
        free_slot(scene, cur);
        cur = p;
    }
    free_slot(scene, root);
}

bool eng_node_is_valid(const eng_scene *scene, eng_node_id id) { return get(scene, id) != NULL; }

bool eng_node_set_local(eng_scene *scene, eng_node_id id, const eng_transform *local)
{
    const char *fn = "eng_node_set_local";
    node *n = use(scene, id, fn);
    if (!n || !check_transform(scene, fn, "local", local)) return false;
    n->local = *local;
    mark_dirty(scene, slot_of(scene, n));
    return true;
}

eng_transform eng_node_get_local(const eng_scene *scene, eng_node_id id)
{
    node *n = use(scene, id, "eng_node_get_local");
    return n ? n->local : eng_identity_transform();
}

static void local_matrix(const eng_transform *t, mat4 m)
{
    versor q = { t->rotation[0], t->rotation[1], t->rotation[2], t->rotation[3] };
    glm_quat_normalize(q);
    glm_quat_mat4(q, m);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) m[c][r] *= t->scale[c];
    m[3][0] = t->translation[0];
    m[3][1] = t->translation[1];
    m[3][2] = t->translation[2];
    m[3][3] = 1.0f;
}

// Brings one node's world matrix up to date, parents first.
static void update_world(eng_scene *s, int slot)
{
    node *n = &s->nodes[slot];
    if (!n->dirty) return;
    mat4 local;
    local_matrix(&n->local, local);
    if (n->parent >= 0) {
        update_world(s, n->parent);
        glm_mat4_mul(s->nodes[n->parent].world, local, n->world);
    } else {
        glm_mat4_copy(local, n->world);
    }
    n->dirty = false;
}

bool eng_node_get_world(eng_scene *scene, eng_node_id id, mat4 out)
{
    node *n = use(scene, id, "eng_node_get_world");
    if (!n) {
        glm_mat4_identity(out);
        return false;
    }
    update_world(scene, slot_of(scene, n));
    glm_mat4_copy(n->world, out);
    return true;
}

bool eng_node_set_parent(eng_scene *scene, eng_node_id id, eng_node_id parent)
{
    const char *fn = "eng_node_set_parent";
    node *n = use(scene, id, fn);
    if (!n) return false;
    int slot = slot_of(scene, n), p = -1;
    if (parent.index1 != 0) {
        node *pn = get(scene, parent);
        if (!pn) {
            eng_log(&scene->def.logger, ENG_LOG_ERROR,
                    "%s: parent must be a live node or ENG_NULL_NODE (got a destroyed node, index %u)", fn,
                    (unsigned)(parent.index1 - 1));
            return false;
        }
        p = slot_of(scene, pn);
        for (int a = p; a >= 0; a = scene->nodes[a].parent) {
            if (a == slot) {
                eng_log(&scene->def.logger, ENG_LOG_ERROR,
                        "%s: parent must not be the node itself or one of its descendants (index %u)", fn,
                        (unsigned)p);
                return false;
            }
        }
    }
    unlink_child(scene, slot);
    link_child(scene, p, slot);
    scene->nodes[slot].dirty = false; // force the subtree walk
    mark_dirty(scene, slot);
    return true;
}

eng_node_id eng_node_get_parent(const eng_scene *scene, eng_node_id id)
{
    node *n = use(scene, id, "eng_node_get_parent");
    return n && n->parent >= 0 ? id_of(scene, n->parent) : ENG_NULL_NODE;
}

bool eng_node_set_mesh(eng_scene *scene, eng_node_id id, eng_mesh_id mesh)
{
    node *n = use(scene, id, "eng_node_set_mesh");
    if (!n) return false;
    n->mesh = mesh;
    return true;
}

eng_mesh_id eng_node_get_mesh(const eng_scene *scene, eng_node_id id)
{
    node *n = use(scene, id, "eng_node_get_mesh");
    return n ? n->mesh : ENG_NULL_MESH;
}

bool eng_node_set_color(eng_scene *scene, eng_node_id id, const float color[3])
{
    const char *fn = "eng_node_set_color";
    node *n = use(scene, id, fn);
    if (!n || !check_color(scene, fn, "color", color)) return false;
    memcpy(n->color, color, sizeof n->color);
    return true;
}

bool eng_node_get_color(const eng_scene *scene, eng_node_id id, float color[3])
{
    node *n = use(scene, id, "eng_node_get_color");
    if (!n) return false;
    memcpy(color, n->color, sizeof n->color);
    return true;
}

bool eng_node_set_visible(eng_scene *scene, eng_node_id id, bool visible)
{
    node *n = use(scene, id, "eng_node_set_visible");
    if (!n) return false;
    n->visible = visible;
    return true;
}

bool eng_node_get_visible(const eng_scene *scene, eng_node_id id)
{
    node *n = use(scene, id, "eng_node_get_visible");
    return n && n->visible;
}

void eng_scene_update(eng_scene *scene)
{
    for (int i = 0; i < scene->count; i++)
        if (scene->nodes[i].live) update_world(scene, i);
}

eng_node_id eng_scene_first(const eng_scene *scene)
{
    for (int i = 0; i < scene->count; i++)
        if (scene->nodes[i].live) return id_of(scene, i);
    return ENG_NULL_NODE;
}

eng_node_id eng_scene_next(const eng_scene *scene, eng_node_id after)
{
    for (int i = (int)after.index1; i < scene->count; i++) // index1 = slot + 1: the next slot
        if (scene->nodes[i].live) return id_of(scene, i);
    return ENG_NULL_NODE;
}

bool eng_node_get_draw(eng_scene *scene, eng_node_id id, eng_node_draw *out)
{
    node *n = use(scene, id, "eng_node_get_draw");
    if (!n) return false;
    int slot = slot_of(scene, n);
    update_world(scene, slot);
    glm_mat4_copy(n->world, out->world);
    out->mesh = n->mesh;
    memcpy(out->color, n->color, sizeof out->color);
    out->visible = true;
    for (int a = slot; a >= 0; a = scene->nodes[a].parent) {
        if (!scene->nodes[a].visible) {
            out->visible = false;
            break;
        }
    }
    return true;
}
