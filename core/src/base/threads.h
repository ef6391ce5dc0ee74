/* A parallel loop over [0, count) on POSIX threads.  Workers take the next chunk of `grain` items
 * from an atomic counter, so any thread may run any item: results must depend only on the item
 * index (see rng_for), never on which thread ran it. */
#ifndef FM_BASE_THREADS_H
#define FM_BASE_THREADS_H

#include "firmament/firmament.h"

#include <stdint.h>

/* Runs items [begin, end) on worker `thread` (0 <= thread < thread count). */
typedef void (*parallel_fn)(void *ctx, int64_t begin, int64_t end, int thread);

typedef struct parallel_progress {
    fm_progress_fn fn; /* may be NULL */
    void *user;
    const char *stage;
    double start, span; /* reported fraction = start + span * done/count */
} parallel_progress;

/* Number of worker threads for a request (0 = online cores), clamped to [1, 256]. */
int parallel_thread_count(int requested);

/* Returns FM_ERR_CANCELLED if *cancel became nonzero (remaining items skipped), FM_ERR_INTERNAL if
 * a thread could not be started and the loop could not run, else FM_OK. */
fm_status parallel_for(int threads, int64_t count, int64_t grain, parallel_fn fn, void *ctx,
                       const atomic_int *cancel, const parallel_progress *progress);

/* Inside a parallel_for item: whether the loop's cancel flag is set, for items that run long (a
 * block of paths at night) to stop early; their partial results are discarded, as the loop then
 * returns FM_ERR_CANCELLED.  0 outside a loop or without a flag. */
int parallel_cancelled(void);

#endif
