#include "image/sidecar.h"

#include "base/platform.h"
#include "base/status.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static cJSON *group_object(cJSON *root, const char *group)
{
    if (!group[0])
        return root;
    cJSON *g = cJSON_GetObjectItemCaseSensitive(root, group);
    if (!g)
        g = cJSON_AddObjectToObject(root, group);
    return g;
}

fm_status sidecar_write(const char *path, const metadata *meta, const char *job, fm_error *err)
{
    cJSON *root = cJSON_CreateObject();
    if (!root)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the sidecar");
    cJSON_AddStringToObject(root, "generator", "firmament");
    for (int i = 0; i < meta->count; i++) {
        const meta_entry *e = &meta->e[i];
        cJSON *g = group_object(root, e->group);
        if (!g)
            continue;
        switch (e->type) {
        case META_DOUBLE:
        case META_INT:
            cJSON_AddNumberToObject(g, e->key, e->v[0]);
            break;
        case META_STRING:
            cJSON_AddStringToObject(g, e->key, e->s);
            break;
        case META_VEC3: {
            cJSON *a = cJSON_AddArrayToObject(g, e->key);
            for (int j = 0; j < 3 && a; j++)
                cJSON_AddItemToArray(a, cJSON_CreateNumber(e->v[j]));
            break;
        }
        }
    }
    /* booleans read better as JSON booleans */
    cJSON *image = cJSON_GetObjectItemCaseSensitive(root, "image");
    cJSON *disk = image ? cJSON_GetObjectItemCaseSensitive(image, "contains_sun_disk") : NULL;
    if (disk)
        cJSON_ReplaceItemInObjectCaseSensitive(image, "contains_sun_disk", cJSON_CreateBool(disk->valuedouble != 0.0));

    cJSON *job_object = job ? cJSON_Parse(job) : NULL;
    if (job_object)
        cJSON_AddItemToObject(root, "job", job_object);

    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the sidecar");
    FILE *f = platform_fopen(path, "w");
    fm_status s = FM_OK;
    if (!f) {
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    } else {
        int ok = fputs(text, f) >= 0 && fputc('\n', f) != EOF;
        ok = (fclose(f) == 0) && ok;
        if (!ok)
            s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    }
    free(text);
    return s;
}
