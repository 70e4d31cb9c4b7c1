// The frame of a report page (pipeline/report/run_report.h, study_report.h): the document head
// with its inline style sheet, and the footer. A page whose work is still going reloads itself
// every 5 s (<meta http-equiv="refresh">) and carries the one script a report has: it keeps the
// scroll position across reloads and, when the page is older than `quietSeconds`, says that the
// work may have stopped. A finished page has neither.
#pragma once

#include <string>

namespace kurage::pipeline {

struct PageHead {
  std::string title;
  bool refresh = false;       // the work is going: reload
  double quietSeconds = 60.0;  // with refresh: how old the page may grow before it says so
};

// From <!DOCTYPE html> to the opening of <main>.
std::string pageStart(const PageHead& head);
// The footer (when the page was written; `command` and what it does, e.g. "redraws it"), the
// script where the head asks for it, and the closing tags.
std::string pageEnd(const PageHead& head, const std::string& command, const std::string& what);

}  // namespace kurage::pipeline
