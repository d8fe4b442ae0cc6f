#pragma once
/// Background threads of the server (render threads, scene builders) run on the CPU time
/// nothing else in it wants, so they never delay a mechanics step.

namespace viscera::server {

/// SCHED_IDLE for the calling thread (which also drops a SCHED_FIFO inherited from a
/// realtime server): a waking mechanics, output or I/O thread preempts it at once; nice 10
/// alone still cost a 1 kHz session 5 % of its deadlines (docs/benchmarks.md, Frame
/// streams). Falls back to nice 19 where SCHED_IDLE is refused.
void LowerThisThreadsPriority();

}  // namespace viscera::server
