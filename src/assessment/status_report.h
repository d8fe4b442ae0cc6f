#pragma once
/// The assessment in session_status_t (protocol 5): a Report written into a status and read
/// back from one, exactly (all figures travel as doubles or integers).
#include <viscera_proto/session_status_t.hpp>

#include "assessment/report.h"

namespace viscera::assessment {

/// Sets the assessment fields of `status` (its num_tools must match the report's tools; the
/// tool names are the status's own).
/// @pre report.tools.size() == status->num_tools.
void FillStatus(const Report& report, viscera_proto::session_status_t* status);

/// The report a status carries: session, scene and time from its header and fields;
/// finished when the status says kStopped or kFaulted.
Report ReportFromStatus(const viscera_proto::session_status_t& status);

}  // namespace viscera::assessment
