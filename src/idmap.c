/* The ID map: linear probing with backward-shift deletion. */
#include <errno.h>
#include <stdlib.h>

#include "idmap.h"

void vis_idmap_init(struct vis_idmap *map)
{
	map->keys = NULL;
	map->values = NULL;
	map->cap = map->count = 0;
}

void vis_idmap_finish(struct vis_idmap *map)
{
	free(map->keys);
	free(map->values);
	vis_idmap_init(map);
}

/* Fibonacci hashing spreads sequential IDs over the table. */
static size_t slot_of(const struct vis_idmap *map, uint32_t key)
{
	return (size_t)((key * 0x9e3779b97f4a7c15ull) >> 32) & (map->cap - 1);
}

void *vis_idmap_get(const struct vis_idmap *map, uint32_t key)
{
	if (!map->cap || !key)
		return NULL;
	for (size_t i = slot_of(map, key);; i = (i + 1) & (map->cap - 1)) {
		if (map->keys[i] == key)
			return map->values[i];
		if (!map->keys[i])
			return NULL;
	}
}

/* Rehashes into a table of cap slots. */
static int grow(struct vis_idmap *map, size_t cap)
{
	struct vis_idmap bigger = { calloc(cap, sizeof(uint32_t)), calloc(cap, sizeof(void *)), cap,
				    0 };
	if (!bigger.keys || !bigger.values) {
		free(bigger.keys);
		free(bigger.values);
		errno = ENOMEM;
		return -1;
	}
	for (size_t i = 0; i < map->cap; i++)
		if (map->keys[i])
			vis_idmap_put(&bigger, map->keys[i], map->values[i]);
	vis_idmap_finish(map);
	*map = bigger;
	return 0;
}

int vis_idmap_put(struct vis_idmap *map, uint32_t key, void *value)
{
	/* A key already there takes the new value in place: replacing never grows, never fails. */
	for (size_t i = map->cap ? slot_of(map, key) : 0; map->cap && map->keys[i];
	     i = (i + 1) & (map->cap - 1))
		if (map->keys[i] == key) {
			map->values[i] = value;
			return 0;
		}
	if ((map->count + 1) * 4 > map->cap * 3 && grow(map, map->cap ? map->cap * 2 : 16) < 0)
		return -1;
	size_t i = slot_of(map, key);
	while (map->keys[i] && map->keys[i] != key)
		i = (i + 1) & (map->cap - 1);
	if (!map->keys[i])
		map->count++;
	map->keys[i] = key;
	map->values[i] = value;
	return 0;
}

void vis_idmap_remove(struct vis_idmap *map, uint32_t key)
{
	if (!map->cap || !key)
		return;
	size_t mask = map->cap - 1, i = slot_of(map, key);
	while (map->keys[i] != key) {
		if (!map->keys[i])
			return;
		i = (i + 1) & mask;
	}
	/* Shift back every later entry of the run that may sit in the freed slot. */
	for (size_t j = (i + 1) & mask; map->keys[j]; j = (j + 1) & mask) {
		size_t home = slot_of(map, map->keys[j]);
		if (((j - home) & mask) >= ((j - i) & mask)) {
			map->keys[i] = map->keys[j];
			map->values[i] = map->values[j];
			i = j;
		}
	}
	map->keys[i] = 0;
	map->values[i] = NULL;
	map->count--;
}
