/* scene_schema.c — the scene schema's table (scene_keys.def) and its
 * Markdown form for docs/scene-format.md. */
#include "scene_schema.h"

#include "scene.h"

#include <math.h>
#include <string.h>

/* a limit's digits in a key's text, from the one macro that states it */
#define SCENE_TEXT_OF(x) #x
#define SCENE_TEXT(x)    SCENE_TEXT_OF(x)

#define REQUIRED         .required = true
#define DEFAULT(x)       .has_default = true, .def = (x)
#define ABOVE(x)         .lo = {true, true, (x)}
#define AT_LEAST(x)      .lo = {true, false, (x)}
#define BELOW(x)         .hi = {true, true, (x)}
#define AT_MOST(x)       .hi = {true, false, (x)}
#define MIN_DIMENSION(n) .min_dimension = (n)
#define WORDS(...)                                                                                 \
    .words = (const char *const[]) {                                                               \
        __VA_ARGS__, NULL                                                                          \
    }
#define TYPE_TEXT(s)    .type_text = (s)
#define DEFAULT_TEXT(s) .default_text = (s)
#define RANGE_TEXT(s)   .range_text = (s)

static const sph_scene_key KEYS[SK_COUNT] = {
#define SCENE_KEY(id, sec, name, kind, meaning, ...)                                               \
    [SK_##id] = {                                                                                  \
        .section = (sec), .key = (name), .type = SCENE_##kind, .text = (meaning), __VA_ARGS__},
#include "scene_keys.def"
#undef SCENE_KEY
};

const sph_scene_key *sph_scene_key_at(sph_scene_key_id id) {
    return (unsigned)id < SK_COUNT ? &KEYS[id] : NULL;
}

int sph_scene_key_words(const sph_scene_key *k) {
    int n = 0;
    while (k->words && k->words[n]) n++;
    return n;
}

static const char *type_text(const sph_scene_key *k) {
    if (k->type_text) return k->type_text;
    switch (k->type) {
    case SCENE_NUMBER:
        return "number";
    case SCENE_INTEGER:
        return "integer";
    case SCENE_BOOLEAN:
        return "boolean";
    case SCENE_STRING:
    case SCENE_KEYWORD:
        return "string";
    case SCENE_NAME:
        return "name";
    case SCENE_VECTOR:
        return "vector";
    case SCENE_GROUP:
        return "group";
    case SCENE_LIST:
        return "list of groups";
    case SCENE_ARRAY:
        return "array of strings";
    case SCENE_EXPRESSION:
        return "number or expression";
    }
    return "?";
}

static void write_default(FILE *out, const sph_scene_key *k) {
    if (k->default_text)
        fputs(k->default_text, out);
    else if (k->required)
        fputs("**required**", out);
    else if (k->has_default && k->type == SCENE_BOOLEAN)
        fprintf(out, "`%s`", k->def != 0.0 ? "true" : "false");
    else if (k->has_default && k->type == SCENE_KEYWORD)
        fprintf(out, "`\"%s\"`", k->words[(int)k->def]);
    else if (k->has_default)
        fprintf(out, "%.15g", k->def);
}

static void write_range(FILE *out, const sph_scene_key *k) {
    if (k->range_text) {
        fputs(k->range_text, out);
        return;
    }
    if (k->type == SCENE_BOOLEAN) {
        fputs("`true`, `false`", out);
        return;
    }
    if (k->type == SCENE_KEYWORD) {
        for (int i = 0; k->words[i]; i++) fprintf(out, "%s`\"%s\"`", i ? ", " : "", k->words[i]);
        return;
    }
    if (k->lo.set && k->hi.set)
        fprintf(out, "%c%.15g, %.15g%c", k->lo.open ? '(' : '[', k->lo.value, k->hi.value,
                k->hi.open ? ')' : ']');
    else if (k->lo.set)
        fprintf(out, "%s %.15g", k->lo.open ? ">" : "≥", k->lo.value);
    else if (k->hi.set)
        fprintf(out, "%s %.15g", k->hi.open ? "<" : "≤", k->hi.value);
}

bool sph_scene_keys_markdown(FILE *out, const char *section) {
    bool any = false;
    for (int i = 0; i < SK_COUNT; i++) {
        const sph_scene_key *k = &KEYS[i];
        if (strcmp(k->section, section) != 0) continue;
        if (!any) {
            fputs("| key | type | default | range / values | meaning |\n", out);
            fputs("|---|---|---|---|---|\n", out);
        }
        any = true;
        fprintf(out, "| `%s` | %s | ", k->key, type_text(k));
        write_default(out, k);
        fputs(" | ", out);
        write_range(out, k);
        fprintf(out, " | %s |\n", k->text);
    }
    return any;
}

int sph_scene_key_sections(const char **names, int max) {
    int n = 0;
    for (int i = 0; i < SK_COUNT; i++) {
        bool seen = false;
        for (int j = 0; j < n && !seen; j++) seen = strcmp(names[j], KEYS[i].section) == 0;
        if (!seen && n < max) names[n++] = KEYS[i].section;
    }
    return n;
}
