#pragma once
// The heap policy of a process that runs a haptic thread: memory the process frees stays in it,
// so the next allocation of that size reuses pages already faulted in instead of faulting fresh
// ones page by page inside a 1 ms tick. glibc by default serves blocks over 128 KB (a threshold
// that then adapts, up to 32 MB) with mmap and unmaps them when freed, and gives the heap's top
// back to the kernel past 128 KB: a coil released or loaded in a tick allocated a rod's arrays
// afresh, ~300 page faults (docs/session/speed.md, "Where the over-budget ticks go").
// Process-wide, kept to the end: the process holds its peak heap. No-op where the C library is
// not glibc (the browser).
namespace cathbox::session {

// Sets the policy (idempotent). A process that also wants one arena for every thread (a
// meshing command reusing one thread's freed memory on another) sets M_ARENA_MAX itself; a
// haptic process does not, so that the haptic thread does not share one arena's lock with all
// the others.
void keep_freed_memory();

}  // namespace cathbox::session
