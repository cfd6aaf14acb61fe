/* cpu_team.h — a barrier of the native backend's OpenMP team that spins,
 * then yields, and never sleeps.
 *
 * A substep's passes are a few tens of microseconds on a small scene (the 2D
 * plate's 1612 particles: about 130 us a substep on two cores).  libgomp's
 * barriers follow OMP_WAIT_POLICY: with `passive` (which shared machines set
 * so that idle threads give their core back) every barrier puts the waiting
 * threads to sleep in the kernel, and waking one costs about as much as the
 * pass, so two passive threads ran the plate slower than one.  Between the
 * passes of a substep, and between the substeps of an advection step run in
 * one parallel region (cpu_kernels.advance), the team synchronises here
 * instead: the arithmetic and the static shares of the loops are those of
 * the OpenMP barriers they replace, so the results are the same bits.  A
 * thread waits by spinning on the barrier's sense for CPU_TEAM_SPINS pauses
 * (about 50 us), then by sched_yield, which lets another process have the
 * core when the machine is oversubscribed. */
#ifndef SPH_CPU_TEAM_H
#define SPH_CPU_TEAM_H

#include <sched.h>
#include <stdatomic.h>

#define CPU_TEAM_SPINS 2000

typedef struct {
    atomic_int arrived; /* threads at the barrier in the current round */
    atomic_int sense;   /* flips when a round completes */
} cpu_team_barrier;

/* A thread's view of the barrier within one parallel region. */
typedef struct {
    cpu_team_barrier *barrier;
    int nthreads;
    int sense;
} cpu_team;

static inline void cpu_team_pause(void) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    __asm__ __volatile__("yield");
#endif
}

/* Enter the team at the start of a parallel region: every thread reads the
 * sense before any can complete the first round (which needs all of them). */
static inline cpu_team cpu_team_enter(cpu_team_barrier *barrier, int nthreads) {
    cpu_team t = {barrier, nthreads, atomic_load_explicit(&barrier->sense, memory_order_acquire)};
    return t;
}

/* Wait until every thread of the team has arrived; what each wrote before
 * is visible to all after (release by the arrivals, acquire by the waits). */
static inline void cpu_team_sync(cpu_team *t) {
    if (t->nthreads < 2) return;
    const int sense = t->sense = !t->sense;
    cpu_team_barrier *b = t->barrier;
    if (atomic_fetch_add_explicit(&b->arrived, 1, memory_order_acq_rel) == t->nthreads - 1) {
        atomic_store_explicit(&b->arrived, 0, memory_order_relaxed);
        atomic_store_explicit(&b->sense, sense, memory_order_release);
        return;
    }
    for (int spins = 0; atomic_load_explicit(&b->sense, memory_order_acquire) != sense;) {
        if (spins < CPU_TEAM_SPINS) {
            ++spins;
            cpu_team_pause();
        } else {
            sched_yield();
        }
    }
}

#endif
