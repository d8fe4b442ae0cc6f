#pragma once
/// The assessment in session_status_t (protocol 5): a Report written into a status and read
/// back from one, exactly (all figures travel as doubles, integers or strings); running the
/// bowel's score in its running_ fields.
#include <viscera_proto/session_status_t.hpp>

#include "assessment/report.h"

namespace viscera::assessment {

/// Sets the assessment fields of `status` (its num_tools must match the report's tools; the
/// tool names are the status's own).
/// @pre report.tools.size() == status->num_tools.
void FillStatus(const Report& report, viscera_proto::session_status_t* status);

/// The report a status carries: session, scene and time from its header and fields;
/// finished when the status says kStopped or kFaulted; running the bowel's score when the
/// status carries one.
Report ReportFromStatus(const viscera_proto::session_status_t& status);

/// The running_ fields of `status` from report.running (all 0 and empty without has_running).
void FillRunningStatus(const Report& report, viscera_proto::session_status_t* status);
/// Running the bowel's score a status carries; false (and `running` empty) when it carries none
/// (running_segments 0).
bool RunningFromStatus(const viscera_proto::session_status_t& status, RunningReport* running);

}  // namespace viscera::assessment
