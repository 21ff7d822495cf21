// The scene graph: nodes with a parent, a local transform, a mesh, a colour and a visible
// flag. World matrices compose parent -> child (world = parent_world * T * R * S).
//
// Nodes are named by eng_node_id values that carry a generation: destroying a node (which
// destroys its whole subtree) makes every id that named one of those nodes stale, and
// eng_node_is_valid() says so; functions given a stale id log "attempt to use a destroyed
// node" and do nothing. The scene is plain memory: no GL calls, usable without a context.
#ifndef ENG_SCENE_H
#define ENG_SCENE_H

#include <cglm/cglm.h>
#include <stdbool.h>
#include <stdint.h>

#include "engine/core/log.h"
#include "engine/render/mesh.h"

typedef struct eng_node_id {
    uint32_t index1;     ///< slot + 1; 0 = null
    uint32_t generation;
} eng_node_id;

/// The null node id (all zero): as a parent it means "the scene root".
#define ENG_NULL_NODE ((eng_node_id){ 0, 0 })

/// A rigid transform with scale: applied as scale, then rotation, then translation.
typedef struct eng_transform {
    float translation[3]; ///< m
    float rotation[4];    ///< unit quaternion x, y, z, w
    float scale[3];       ///< per axis, non-zero
} eng_transform;

/// translation 0, rotation identity (0, 0, 0, 1), scale 1.
eng_transform eng_identity_transform(void);

typedef struct eng_scene_def {
    int max_nodes;     ///< capacity: 1..1048576
    eng_logger logger; ///< input errors and stale ids are reported here
} eng_scene_def;

eng_scene_def eng_default_scene_def(void);

typedef struct eng_node_def {
    eng_node_id parent;    ///< ENG_NULL_NODE for a top-level node
    eng_transform local;   ///< relative to the parent
    eng_mesh_id mesh;      ///< ENG_NULL_MESH for a node without geometry (a group)
    float color[3];        ///< linear RGB, each 0..1
    bool visible;          ///< a hidden node hides its subtree too
} eng_node_def;

/// No parent, identity transform, no mesh, light grey (0.8, 0.8, 0.8), visible.
eng_node_def eng_default_node_def(void);

typedef struct eng_scene eng_scene;

/// NULL with a logged message when the def is out of range.
eng_scene *eng_scene_create(const eng_scene_def *def);
void eng_scene_destroy(eng_scene *scene);
int eng_scene_node_count(const eng_scene *scene);

/// Creates a node; returns ENG_NULL_NODE (and logs which field is wrong) when the def is
/// invalid: a stale parent, a non-unit rotation, a zero or non-finite scale, a colour
/// outside 0..1, or a full scene.
eng_node_id eng_node_create(eng_scene *scene, const eng_node_def *def);
/// Destroys the node and all its descendants. A stale id is logged and ignored.
void eng_node_destroy(eng_scene *scene, eng_node_id id);
/// True while the node exists (false for ENG_NULL_NODE and ids of destroyed nodes).
bool eng_node_is_valid(const eng_scene *scene, eng_node_id id);

bool eng_node_set_local(eng_scene *scene, eng_node_id id, const eng_transform *local);
/// The local transform; identity for a stale id.
eng_transform eng_node_get_local(const eng_scene *scene, eng_node_id id);
/// The world matrix (column-major, cglm mat4): parent's world * local. Identity and false
/// for a stale id. Recomputes only what changed since the last call.
bool eng_node_get_world(eng_scene *scene, eng_node_id id, mat4 out);
/// Moves a node under another parent (ENG_NULL_NODE = top level); refuses cycles.
bool eng_node_set_parent(eng_scene *scene, eng_node_id id, eng_node_id parent);
eng_node_id eng_node_get_parent(const eng_scene *scene, eng_node_id id);
bool eng_node_set_mesh(eng_scene *scene, eng_node_id id, eng_mesh_id mesh);
eng_mesh_id eng_node_get_mesh(const eng_scene *scene, eng_node_id id);
bool eng_node_set_color(eng_scene *scene, eng_node_id id, const float color[3]);
bool eng_node_get_color(const eng_scene *scene, eng_node_id id, float color[3]);
bool eng_node_set_visible(eng_scene *scene, eng_node_id id, bool visible);
/// The node's own flag (not whether an ancestor hides it).
bool eng_node_get_visible(const eng_scene *scene, eng_node_id id);

/// Brings every world matrix up to date (done lazily by eng_node_get_world as well).
void eng_scene_update(eng_scene *scene);

/// Iteration over live nodes in slot order:
///   for (eng_node_id n = eng_scene_first(s); n.index1; n = eng_scene_next(s, n)) ...
eng_node_id eng_scene_first(const eng_scene *scene);
eng_node_id eng_scene_next(const eng_scene *scene, eng_node_id after);

/// What the renderer needs of one node, after eng_scene_update: the world matrix, the mesh,
/// the colour, and whether it and all its ancestors are visible. False for a stale id.
typedef struct eng_node_draw {
    mat4 world;
    eng_mesh_id mesh;
    float color[3];
    bool visible;
} eng_node_draw;
bool eng_node_get_draw(eng_scene *scene, eng_node_id id, eng_node_draw *out);

#endif
