/* A map from 32-bit IDs to pointers: the daemon's window and client lookup. */
#ifndef VIS_IDMAP_H
#define VIS_IDMAP_H

#include <stddef.h>
#include <stdint.h>

/*
 * Open addressing with linear probing and backward-shift deletion (no tombstones), so a lookup
 * never walks past the first empty slot. Invariants: cap is 0 or a power of two; at most
 * 3/4 of the slots are used; key 0 marks an empty slot, so 0 cannot be stored.
 */
struct vis_idmap {
	uint32_t *keys;
	void **values;
	size_t cap, count;
};

void vis_idmap_init(struct vis_idmap *map);
void vis_idmap_finish(struct vis_idmap *map);

/* The value stored for key, or NULL. Expected O(1). */
void *vis_idmap_get(const struct vis_idmap *map, uint32_t key);

/*
 * Stores value (not NULL) for key (not 0), replacing any. 0, or -1 with ENOMEM (never when key
 * is there already). Amortized O(1).
 */
int vis_idmap_put(struct vis_idmap *map, uint32_t key, void *value);

/* Removes key if present. Expected O(1). */
void vis_idmap_remove(struct vis_idmap *map, uint32_t key);

#endif
