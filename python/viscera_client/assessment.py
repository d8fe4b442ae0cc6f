"""The assessment a session's status carries (protocol 5; docs/assessment.md), running the
bowel's score included (docs/training.md), as the same JSON-shaped dict `viscera report --json`
prints and viscerad writes beside the record."""


def report_from_status(status):
    """dict of the assessment in session_status_t `status` (keys as in docs/assessment.md)."""
    tools = []
    for i in range(min(status.num_tools, len(status.tool_path_length))):
        tools.append({
            "name": status.tool_names[i],
            "path_length_m": status.tool_path_length[i],
            "active_time_s": status.tool_active_time[i],
            "tissue_force_n": {"p50": status.tool_force_p50[i], "p95": status.tool_force_p95[i],
                               "max": status.tool_force_max[i]},
            "tissue_contact_time_s": status.tool_contact_time[i],
            "traction_events": status.tool_traction_events[i],
            "traction_time_s": status.tool_traction_time[i],
            "grasps": status.tool_grasps[i],
            "regrasps": status.tool_regrasps[i],
            "organ_contacts": status.tool_organ_contacts[i],
            "organ_contact_time_s": status.tool_organ_contact_time[i],
        })
    targets = []
    for i in range(status.num_targets):
        t = status.target_time_to_expose[i]
        targets.append({"name": status.target_names[i], "exposed": status.target_exposed[i],
                        "max_exposed": status.target_max_exposed[i],
                        "time_to_expose_s": t if t >= 0.0 else None})
    stopped = status.state in (status.kStopped, status.kFaulted)
    running = running_from_status(status)
    return {
        "session": status.header.session_id,
        "scene": status.scene,
        "sim_time_s": status.sim_time,
        "finished": stopped,
        "thresholds": {"traction_force_n": status.traction_force, "traction_hold_s": status.traction_hold,
                       "regrasp_window_s": status.regrasp_window, "exposed_fraction": status.exposed_fraction},
        "tools": tools,
        "targets": targets,
        "running": running,
    }


def running_from_status(status):
    """dict of running the bowel's score in `status` (keys as `viscera report --json`'s
    "running"), or None when it carries none (older servers, scenes without [running])."""
    if getattr(status, "running_segments", 0) <= 0:
        return None
    s = status
    events = [{"kind": s.running_event_kinds[i], "segment": s.running_event_segments[i],
               "tool": s.running_event_tools[i], "t_s": s.running_event_times[i],
               "value": s.running_event_values[i]} for i in range(s.running_num_events)]
    return {
        "segments": s.running_segments,
        "segment_length_m": s.running_segment_length,
        "coverage": s.running_coverage,
        "missed": list(s.running_missed),
        "reversals": s.running_reversals,
        "grasps": s.running_grasps,
        "regrasps": s.running_regrasps,
        "slips": s.running_slips,
        "path_length_m": s.running_path_length,
        "instrument_collisions": s.running_instrument_collisions,
        "out_of_view_time_s": s.running_out_of_view_time,
        "time_s": s.running_time,
        "max_grip_n": s.running_max_grip,
        "max_pressure_pa": s.running_max_pressure,
        "max_traction_n": s.running_max_traction,
        "max_dose_ns": s.running_max_dose,
        "events": events,
        "damaged": list(s.running_damaged),
        "run_length_m": s.running_run_length,
        "estimate_length_m": s.running_estimate_length,
        "estimate_error": s.running_estimate_error,
        "passed": bool(s.running_passed),
        "failed": list(s.running_failed),
        "thresholds": {"pinch_force_n": s.running_pinch_force, "damage_dose_ns": s.running_damage_dose,
                       "traction_break_n": s.running_traction_break, "jaw_area_m2": s.running_jaw_area},
        "pass_marks": {"coverage": s.running_pass_coverage, "time_s": s.running_pass_time,
                       "path_length_m": s.running_pass_path,
                       "out_of_view_time_s": s.running_pass_out_of_view, "reversals": s.running_pass_reversals,
                       "slips": s.running_pass_slips, "damage_events": s.running_pass_damage_events,
                       "estimate_error": s.running_pass_estimate_error},
    }
