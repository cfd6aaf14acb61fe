/* scene_schema.h — every key a scene file may hold, stated once.
 *
 * One table (scene_keys.def, expanded in scene_schema.c) gives each key its
 * section, name, type, whether it is required, its default, its range or
 * words, and what it means.  The loader reads keys through it (check_keys
 * accepts a section's keys and no others; the typed getters take the range
 * and the default from it), and `sphsolid scene-keys` writes the key tables
 * of docs/scene-format.md from it (tools/scene_keys_doc.py; the test
 * test_scene_docs fails when the document and the table differ).
 */
#ifndef SPH_SCENE_SCHEMA_H
#define SPH_SCENE_SCHEMA_H

#include <stdbool.h>
#include <stdio.h>

typedef enum {
    SCENE_NUMBER,     /* a finite number; an integer literal is accepted */
    SCENE_INTEGER,    /* an integer, read as 64 bits */
    SCENE_BOOLEAN,    /* true or false */
    SCENE_STRING,     /* free text or a path */
    SCENE_NAME,       /* a string naming a table entry (material, shape, observer) */
    SCENE_KEYWORD,    /* a string from `words` */
    SCENE_VECTOR,     /* `dimension` numbers unless the text says otherwise */
    SCENE_GROUP,      /* { ... } */
    SCENE_LIST,       /* ( { ... }, ... ) */
    SCENE_ARRAY,      /* [ ... ] or ( ... ) of strings: names, axes, fields */
    SCENE_EXPRESSION, /* a number, or a string: an expression of x, y, z */
} sph_scene_value;

/* A bound of a number's or an integer's range; unset: none. */
typedef struct {
    bool set;
    bool open; /* the bound itself is excluded */
    double value;
} sph_scene_bound;

typedef struct {
    const char *section; /* "" for the top level, else as docs/scene-format.md names it */
    const char *key;
    sph_scene_value type;
    bool required;    /* absent is an error (some keys are required by the loader
                         only in some scenes: their default_text says when) */
    bool has_default; /* numbers, integers, booleans, keywords (def: the word's index) */
    double def;
    sph_scene_bound lo, hi;
    int min_dimension;        /* a key of scenes of at least this dimension (0: any) */
    const char *const *words; /* keywords: NULL-terminated, in the order of the enum read */
    const char *type_text;    /* the docs' type when not the type's name */
    const char *default_text; /* the docs' default when not the number or word itself */
    const char *range_text;   /* the docs' range when not the bounds or words */
    const char *text;         /* what it means (Markdown) */
} sph_scene_key;

typedef enum {
#define SCENE_KEY(id, ...) SK_##id,
#include "scene_keys.def"
#undef SCENE_KEY
    SK_COUNT
} sph_scene_key_id;

/* The table, indexed by sph_scene_key_id. */
const sph_scene_key *sph_scene_key_at(sph_scene_key_id id);

/* Number of words of a keyword key. */
int sph_scene_key_words(const sph_scene_key *k);

/* Writes the Markdown table of a section's keys (| key | type | default |
 * range / values | meaning |); false when no key has that section. */
bool sph_scene_keys_markdown(FILE *out, const char *section);

/* The sections, in table order, without repeats: *n of them into names[]
 * (at most `max`). */
int sph_scene_key_sections(const char **names, int max);

#endif
