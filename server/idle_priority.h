#pragma once
/// Background threads of the server (render threads, scene builders) run on the CPU time
/// nothing else in it wants, so they never delay a mechanics step.

namespace viscera::server {

/// SCHED_IDLE for the calling thread (which also drops a SCHED_FIFO inherited from a
/// realtime server): a waking mechanics, output or I/O thread preempts it at once; nice 10
/// alone still cost a 1 kHz session 5 % of its deadlines (docs/server-benchmarks.md,
/// Frame streams). Falls back to nice 19 where SCHED_IDLE is refused.
void LowerThisThreadsPriority();

/// nice 10 for the calling thread (SCHED_OTHER, which also drops an inherited SCHED_FIFO): for
/// work a client waits for, such as building a scene. It yields to the sessions' threads but is
/// never starved: at SCHED_IDLE a create waited for minutes, and timed out, whenever any other
/// process kept the cores busy.
void NiceThisThread();

}  // namespace viscera::server
