// The report's "Sequences" part (CONTRACT §10): a summary of every sequence point (suite_report_
// sequences_summary.h: a sortable table ranked on true steady_rmse_excess, one overlay chart of
// rmse_excess by frame per scene view), then each point's section, folded in a <details>,
// from what the runner kept in the
// point's folder (harness/sweep/kept_sequence.h: sequence.json, the kept frames' estimate and
// reference EXRs): the §10 keys; a strip of frames (reference | estimate | |error|, one row each
// for the first frame, the frame with most disoccluded pixels and the last, one error scale for
// all three) inside the viewer (CONTRACT §11) over every kept frame, with its frame slider and
// play; a video of the estimate beside the reference (viewer.h video_html: drawn in the page from
// the viewer's data, not a second copy of the frames); and rmse_excess by frame and by frames
// since disocclusion
// (matplotlib); and its flicker and lag maps in the viewer. Internal to reports/suite_report.
#pragma once

#include <string>

#include "harness/results/suite_record.h"
#include "reports/html.h"

namespace aoeval {

// Draws every sequence point's strip and chart into its folder (kept when newer than
// their sources) and returns the HTML of the report's "Sequences" part: "" when no ok row of
// `report` is a sequence point whose entry names its manifest (role "sequence", from the store).
// InputError naming the file when a manifest or an EXR it names cannot be read.
Html sequence_sections(const std::string& out_dir, const SuiteReport& report);

}  // namespace aoeval
