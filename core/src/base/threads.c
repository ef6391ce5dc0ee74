#include "base/threads.h"

#include "base/platform.h"

#include <pthread.h>
#include <stdlib.h>

typedef struct pool_job {
    parallel_fn fn;
    void *ctx;
    int64_t count, grain;
    atomic_llong next;    /* first item of the next free chunk */
    atomic_llong done;    /* items finished */
    atomic_int stopped;   /* set once a cancel was seen */
    const atomic_int *cancel;
    const parallel_progress *progress;
} pool_job;

typedef struct worker_arg {
    pool_job *job;
    int thread;
} worker_arg;

int parallel_thread_count(int requested)
{
    long n = requested > 0 ? requested : platform_cpu_count();
    if (n < 1)
        n = 1;
    if (n > 256)
        n = 256;
    return (int)n;
}

/* the cancel flag of the loop whose item this thread runs (parallel_cancelled) */
static _Thread_local const atomic_int *current_cancel;

int parallel_cancelled(void)
{
    return current_cancel && atomic_load_explicit(current_cancel, memory_order_relaxed);
}

static void *worker_main(void *p)
{
    worker_arg *arg = p;
    pool_job *job = arg->job;
    const atomic_int *outer = current_cancel; /* the calling thread may be inside another loop */
    current_cancel = job->cancel;
    for (;;) {
        if (job->cancel && atomic_load(job->cancel)) {
            atomic_store(&job->stopped, 1);
            break;
        }
        int64_t begin = atomic_fetch_add(&job->next, job->grain);
        if (begin >= job->count)
            break;
        int64_t end = begin + job->grain < job->count ? begin + job->grain : job->count;
        job->fn(job->ctx, begin, end, arg->thread);
        int64_t done = atomic_fetch_add(&job->done, end - begin) + (end - begin);
        /* Only the calling thread reports, so the callback never runs concurrently. */
        const parallel_progress *pr = job->progress;
        if (arg->thread == 0 && pr && pr->fn)
            pr->fn(pr->user, pr->start + pr->span * (double)done / (double)job->count, pr->stage);
    }
    current_cancel = outer;
    return NULL;
}

fm_status parallel_for(int threads, int64_t count, int64_t grain, parallel_fn fn, void *ctx,
                       const atomic_int *cancel, const parallel_progress *progress)
{
    if (count <= 0)
        return FM_OK;
    if (grain < 1)
        grain = 1;
    threads = parallel_thread_count(threads);
    if (threads > (count + grain - 1) / grain)
        threads = (int)((count + grain - 1) / grain);

    pool_job job = {.fn = fn, .ctx = ctx, .count = count, .grain = grain, .cancel = cancel,
                    .progress = progress};
    atomic_init(&job.next, 0);
    atomic_init(&job.done, 0);
    atomic_init(&job.stopped, 0);

    pthread_t *tids = calloc((size_t)threads, sizeof *tids);
    worker_arg *args = calloc((size_t)threads, sizeof *args);
    if (!tids || !args) {
        free(tids);
        free(args);
        return FM_ERR_OUT_OF_MEMORY;
    }
    int started = 1;
    for (int t = 1; t < threads; t++) {
        args[t] = (worker_arg){&job, t};
        if (pthread_create(&tids[t], NULL, worker_main, &args[t]) != 0)
            break; /* fewer workers is still correct */
        started++;
    }
    args[0] = (worker_arg){&job, 0};
    worker_main(&args[0]);
    for (int t = 1; t < started; t++)
        pthread_join(tids[t], NULL);
    free(tids);
    free(args);
    if (atomic_load(&job.stopped) || (cancel && atomic_load(cancel)))
        return FM_ERR_CANCELLED;
    return FM_OK;
}
