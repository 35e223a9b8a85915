#include <malloc.h>

#include <cstdlib>

#include "backends.hpp"

namespace rdsim::render {

// Process-wide settings that make per-frame software rendering (Mesa llvmpipe, through OSMesa or
// EGL) cheap. They must be in place before Mesa creates its first context (llvmpipe reads
// LP_NUM_THREADS once, when it starts), so the backends apply them, once, rather than leaving it to
// every program that renders. Measured on the 2-core dev box, Release, one thread:
//  - Mesa allocates and frees large scratch buffers on every draw. By default glibc gives the top
//    of the heap back to the OS each time (brk) and faults it back in next frame (perf: 26% of the
//    time in page faults), and mmaps/unmaps buffers above 128 KiB. A 512 MiB trim threshold and the
//    largest mmap threshold keep them in the heap: inmoov_tomato 64x64 render 2,600 -> 500 us per
//    frame; jaka_button 224x224 750 -> 2,300 steps/s.
//  - llvmpipe's rasteriser threads (one per core by default) cost more in hand-offs than they save
//    on images this small, and an env step must stay on one thread: LP_NUM_THREADS=0 draws in the
//    calling thread (jaka_button 64x64: 3,100 -> 11,500 steps/s). A value set by the user wins.
void tune_process_for_software_rendering() {
  static const bool once = [] {
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest; the call above froze it at 128 KiB
    setenv("LP_NUM_THREADS", "0", 0);
    return true;
  }();
  (void)once;
}

}  // namespace rdsim::render
