"""The assessment a session's status carries (protocol 5; docs/assessment.md), as the same
JSON-shaped dict `viscera report --json` prints and viscerad writes beside the record."""


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
    return {
        "session": status.header.session_id,
        "scene": status.scene,
        "sim_time_s": status.sim_time,
        "finished": stopped,
        "thresholds": {"traction_force_n": status.traction_force, "traction_hold_s": status.traction_hold,
                       "regrasp_window_s": status.regrasp_window, "exposed_fraction": status.exposed_fraction},
        "tools": tools,
        "targets": targets,
    }
