// Timers (seiche.after, seiche.every): a binary heap of their next firings, ordered by due
// time and then slot (the order the timers have always fired in), fired after on_step. A
// cancelled timer's entry stays in the heap until it comes up (or the heap is rebuilt) and
// is skipped: its slot was released or reused with a new generation.
#include "engine/script/script_internal.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool before(const timer_entry *a, const timer_entry *b)
{
    return a->due < b->due || (a->due == b->due && a->slot < b->slot);
}

static void sift_up(timer_entry *h, uint32_t i)
{
    while (i > 0) {
        uint32_t parent = (i - 1) / 2;
        if (!before(&h[i], &h[parent])) break;
        timer_entry t = h[i];
        h[i] = h[parent];
        h[parent] = t;
        i = parent;
    }
}

static void sift_down(timer_entry *h, uint32_t n, uint32_t i)
{
    for (;;) {
        uint32_t l = 2 * i + 1, r = l + 1, m = i;
        if (l < n && before(&h[l], &h[m])) m = l;
        if (r < n && before(&h[r], &h[m])) m = r;
        if (m == i) return;
        timer_entry t = h[i];
        h[i] = h[m];
        h[m] = t;
        i = m;
    }
}

// The live timer an entry names, or NULL when it is stale.
static obj *entry_timer(eng_script *s, const timer_entry *e)
{
    obj *o = scr_obj_at(s, e->slot, e->gen);
    return o && o->kind == OBJ_TIMER && o->state == OBJ_LIVE && o->u.timer.due == e->due ? o : NULL;
}

// Drops the stale entries (cancelled timers) when they are most of the heap.
static void compact(eng_script *s)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->timer_count; i++)
        if (entry_timer(s, &s->timers[i])) s->timers[n++] = s->timers[i];
    s->timer_count = n;
    for (uint32_t i = n / 2; i-- > 0;) sift_down(s->timers, n, i);
}

void scr_timer_reserve(lua_State *L, eng_script *s)
{
    if (s->timer_count < s->timer_cap) return;
    compact(s);
    if (s->timer_cap && s->timer_count <= s->timer_cap / 2) return; // half of it was stale
    uint32_t cap = s->timer_cap ? 2 * s->timer_cap : 64;
    size_t more = (size_t)(cap - s->timer_cap) * sizeof(timer_entry);
    scr_charge(L, s, "seiche.after/every", more);
    timer_entry *h = realloc(s->timers, (size_t)cap * sizeof *h);
    if (!h) {
        scr_uncharge(s, more);
        scr_raise(L, "seiche: out of memory for timers");
    }
    s->timers = h;
    s->timer_cap = cap;
}

void scr_timer_schedule(eng_script *s, uint32_t slot)
{
    assert(s->timer_count < s->timer_cap);
    const obj *o = &s->objs[slot];
    s->timers[s->timer_count] = (timer_entry){ o->u.timer.due, slot, o->generation };
    sift_up(s->timers, s->timer_count++);
}

static void pop(eng_script *s)
{
    s->timers[0] = s->timers[--s->timer_count];
    sift_down(s->timers, s->timer_count, 0);
}

// "file:line" where the timer's function was defined.
static void timer_origin(eng_script *s, int fn, char *buf, size_t size)
{
    lua_Debug ar;
    lua_rawgeti(s->L, LUA_REGISTRYINDEX, fn);
    if (lua_getinfo(s->L, ">S", &ar) && ar.linedefined > 0) snprintf(buf, size, "%s:%d", ar.short_src, ar.linedefined);
    else snprintf(buf, size, "%s", s->path);
}

eng_script_status scr_fire_timers(eng_script *s, double time,
                                  eng_script_status (*call)(eng_script *s, int fn_ref, double time))
{
    int calls = 0;
    while (s->timer_count > 0 && s->timers[0].due <= time + 1e-9) {
        timer_entry e = s->timers[0];
        pop(s);
        obj *o = entry_timer(s, &e);
        if (!o) continue;
        int fn = o->u.timer.fn;
        if (++calls > SCR_MAX_TIMER_CALLS) {
            char where[600];
            timer_origin(s, fn, where, sizeof where);
            snprintf(s->error, sizeof s->error, "%s: more than %d timer calls were due in one frame (at t = %g s; this "
                     "timer's period is %g s, the frame's step %g s): lengthen the timers' periods", where,
                     SCR_MAX_TIMER_CALLS, time, o->u.timer.period, s->host.dt);
            return ENG_SCRIPT_ERROR;
        }
        bool repeat = o->u.timer.period > 0;
        if (repeat) {
            o->u.timer.due += o->u.timer.period;
            scr_timer_schedule(s, e.slot); // in the room of the entry just popped
        } else {
            o->u.timer.fn = LUA_NOREF; // the call below still needs the function
            scr_obj_release(s, e.slot); // one-shot: done before it runs (it may make new timers)
        }
        eng_script_status st = call(s, fn, time);
        if (!repeat) luaL_unref(s->L, LUA_REGISTRYINDEX, fn);
        if (st != ENG_SCRIPT_OK) return st;
    }
    return ENG_SCRIPT_OK;
}
