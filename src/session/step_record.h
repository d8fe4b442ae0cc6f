#pragma once
/// step_record_t <-> tool targets: the exact inputs of one mechanics event, as the session
/// record keeps them for replay.
#include <span>
#include <vector>

#include <viscera_proto/step_record_t.hpp>

#include "mechanics/tool.h"
#include "session/inbox.h"

namespace viscera::session {

/// Fills `record` (all but its header) with `kind`, the step count before the event, each
/// tool's target and the seq of the pose it came from (poses[i].seq; -1 when poses is
/// shorter). Reuses record's arrays.
void FillStepRecord(int8_t kind, int64_t step, std::span<const mechanics::ToolTarget> targets,
                    std::span<const PoseInput> poses, viscera_proto::step_record_t* record);

/// The targets a record holds (resized to its num_tools).
/// @return false when the record is inconsistent (num_tools vs array, non-finite values).
bool TargetsOf(const viscera_proto::step_record_t& record,
               std::vector<mechanics::ToolTarget>* targets);

}  // namespace viscera::session
