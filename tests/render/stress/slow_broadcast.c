// LD_PRELOAD shim for scripts/stress_llvmpipe_threads.sh (issue 37, docs/rendering.md,
// "llvmpipe's rasterizer threads"). A thread named llvmpipe-N that broadcasts a condition variable
// sleeps 2 ms first, as a rasterizer thread preempted inside lp_fence_signal would. Correct code
// cannot depend on that timing; Mesa 22.3's llvmpipe does: the drawing thread sees the fence's
// count complete without taking its mutex and frees the fence under the sleeping broadcaster.
// With glibc's MALLOC_PERTURB_ the freed condition variable then holds 0xA5 bytes and the
// broadcast waits forever; without it, it writes into freed heap.
//   cc -O2 -shared -fPIC slow_broadcast.c -o slow_broadcast.so -ldl
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static atomic_long slowed;

int pthread_cond_broadcast(pthread_cond_t* cond) {
  static int (*real)(pthread_cond_t*);
  if (real == NULL)
    real = (int (*)(pthread_cond_t*))dlvsym(RTLD_NEXT, "pthread_cond_broadcast", "GLIBC_2.3.2");
  char name[16] = "";
  pthread_getname_np(pthread_self(), name, sizeof name);
  if (strncmp(name, "llvmpipe", 8) == 0) {
    const struct timespec pause = {0, 2000000};
    nanosleep(&pause, NULL);
    atomic_fetch_add(&slowed, 1);
  }
  return real(cond);
}

__attribute__((destructor)) static void Report(void) {
  fprintf(stderr, "slow_broadcast: %ld broadcasts of llvmpipe threads slowed\n", (long)slowed);
}
