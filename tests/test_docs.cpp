// The documentation keeps itself honest (docs/README.md, "Conventions"): every relative link and
// image in README.md and docs/ resolves, anchors included; every table of a results page sits
// under a `Command:` line that names what regenerates it; every such command names a `kurage`
// subcommand that exists (`kurage SUB [SUBSUB] --help` succeeds), a script of the repository, or
// ctest; and the user's and design pages carry no history (no dates, no issue numbers), which
// belongs in docs/notebook/. Each check is also run on a small broken tree, so each can fail.
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace kurage;

namespace {

std::vector<std::string> readLines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

std::string trimLeft(const std::string& s) {
  const auto i = s.find_first_not_of(" \t");
  return i == std::string::npos ? "" : s.substr(i);
}

// The lines of a Markdown file outside fenced code blocks, with their line numbers (1-based).
std::vector<std::pair<int, std::string>> proseLines(const fs::path& file) {
  std::vector<std::pair<int, std::string>> out;
  bool fenced = false;
  int number = 0;
  for (const std::string& line : readLines(file)) {
    ++number;
    if (startsWith(trimLeft(line), "```")) {
      fenced = !fenced;
      continue;
    }
    if (!fenced) out.emplace_back(number, line);
  }
  return out;
}

// The code spans of a line (`...`), in order.
std::vector<std::string> codeSpans(const std::string& line) {
  std::vector<std::string> spans;
  std::size_t i = 0;
  while ((i = line.find('`', i)) != std::string::npos) {
    const std::size_t end = line.find('`', i + 1);
    if (end == std::string::npos) break;
    spans.push_back(line.substr(i + 1, end - i - 1));
    i = end + 1;
  }
  return spans;
}

// The line with each code span's content blanked (its backticks kept), so that brackets inside
// code are not read as links.
std::string withoutCode(const std::string& line) {
  std::string out = line;
  bool inside = false;
  for (char& c : out) {
    if (c == '`') inside = !inside;
    else if (inside) c = ' ';
  }
  return out;
}

// GitHub's anchor of a heading: lower case; letters, digits, '-' and '_' kept (non-ASCII letters
// of the Latin, Greek and Cyrillic blocks too); spaces become '-'; everything else is dropped.
std::string slug(const std::string& heading) {
  std::string out;
  for (std::size_t i = 0; i < heading.size();) {
    const unsigned char c = static_cast<unsigned char>(heading[i]);
    if (c < 0x80) {
      if (std::isalnum(c) || c == '-' || c == '_') out += static_cast<char>(std::tolower(c));
      else if (c == ' ') out += '-';
      ++i;
      continue;
    }
    const int length = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : 2;
    unsigned code = c & (length == 2 ? 0x1F : length == 3 ? 0x0F : 0x07);
    for (int k = 1; k < length && i + k < heading.size(); ++k)
      code = (code << 6) | (static_cast<unsigned char>(heading[i + k]) & 0x3F);
    const bool letter = (code >= 0xC0 && code <= 0x24F && code != 0xD7 && code != 0xF7) ||
                        (code >= 0x370 && code <= 0x3FF) || (code >= 0x400 && code <= 0x4FF);
    if (letter) out += heading.substr(i, length);  // GitHub lower-cases these too; ours are written so
    i += length;
  }
  return out;
}

// The anchors a Markdown file offers: its headings' slugs (a repeated heading gets -1, -2, ...)
// and explicit <a id="..."> / <a name="...">.
std::set<std::string> anchorsOf(const fs::path& file) {
  std::set<std::string> anchors;
  std::map<std::string, int> seen;
  static const std::regex html(R"re(<a\s+(?:id|name)="([^"]+)")re");
  for (const auto& [number, line] : proseLines(file)) {
    if (startsWith(line, "#")) {
      std::string text = line.substr(line.find_first_not_of('#'));
      text = trimLeft(text);
      std::string plain;
      for (char c : text)
        if (c != '`' && c != '*') plain += c;
      // A link in a heading counts by its text.
      plain = std::regex_replace(plain, std::regex(R"re(\[([^\]]*)\]\([^)]*\))re"), "$1");
      const std::string base = slug(plain);
      const int n = seen[base]++;
      anchors.insert(n == 0 ? base : base + "-" + std::to_string(n));
    }
    for (std::sregex_iterator m(line.begin(), line.end(), html), end; m != end; ++m) anchors.insert((*m)[1]);
  }
  return anchors;
}

// README.md and every .md file under docs/, relative to the root.
std::vector<fs::path> documents(const fs::path& root) {
  std::vector<fs::path> files;
  if (fs::exists(root / "README.md")) files.push_back("README.md");
  if (fs::exists(root / "docs"))
    for (const auto& entry : fs::recursive_directory_iterator(root / "docs"))
      if (entry.is_regular_file() && entry.path().extension() == ".md")
        files.push_back(fs::relative(entry.path(), root));
  std::sort(files.begin(), files.end());
  return files;
}

bool isExternal(const std::string& target) {
  static const std::regex scheme(R"re(^[a-zA-Z][a-zA-Z0-9+.-]*:)re");
  return std::regex_search(target, scheme);
}

// Every relative link or image of the documents that does not resolve: "FILE:LINE: TARGET (why)".
std::vector<std::string> brokenLinks(const fs::path& root) {
  std::vector<std::string> problems;
  static const std::regex inlineLink(R"re(\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\))re");
  static const std::regex referenceLink(R"re(^\s*\[[^\]]+\]:\s+(\S+))re");
  const fs::path canonicalRoot = fs::weakly_canonical(root);
  std::map<fs::path, std::set<std::string>> anchorCache;
  for (const fs::path& document : documents(root)) {
    for (const auto& [number, rawLine] : proseLines(root / document)) {
      const std::string line = withoutCode(rawLine);
      std::vector<std::string> targets;
      for (std::sregex_iterator m(line.begin(), line.end(), inlineLink), end; m != end; ++m)
        targets.push_back((*m)[1]);
      std::smatch ref;
      if (std::regex_search(line, ref, referenceLink)) targets.push_back(ref[1]);
      for (const std::string& target : targets) {
        if (isExternal(target)) continue;
        const std::string where = document.string() + ":" + std::to_string(number) + ": " + target;
        const std::size_t hash = target.find('#');
        const std::string pathPart = target.substr(0, hash);
        const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
        const fs::path resolved =
            pathPart.empty() ? root / document : fs::weakly_canonical(root / document.parent_path() / pathPart);
        if (!pathPart.empty()) {
          const std::string relative = fs::relative(resolved, canonicalRoot).string();
          if (relative.empty() || startsWith(relative, "..")) {
            problems.push_back(where + " (outside the repository)");
            continue;
          }
          if (!fs::exists(resolved)) {
            problems.push_back(where + " (no such file)");
            continue;
          }
        }
        if (!anchor.empty()) {
          if (resolved.extension() != ".md") continue;  // anchors are checked in Markdown only
          auto it = anchorCache.find(resolved);
          if (it == anchorCache.end()) it = anchorCache.emplace(resolved, anchorsOf(resolved)).first;
          if (!it->second.count(anchor)) problems.push_back(where + " (no such heading)");
        }
      }
    }
  }
  return problems;
}

bool isResultsPage(const fs::path& document) { return startsWith(document.generic_string(), "docs/results/"); }

bool isCommandLine(const std::string& line) {
  const std::string t = trimLeft(line);
  return startsWith(t, "Command:") || startsWith(t, "Commands:");
}

// Every table of a results page that has no `Command:` line between its section's heading and
// itself: "FILE:LINE".
std::vector<std::string> tablesWithoutCommand(const fs::path& root) {
  std::vector<std::string> problems;
  for (const fs::path& document : documents(root)) {
    if (!isResultsPage(document)) continue;
    bool commandInSection = false;
    bool inTable = false;
    for (const auto& [number, line] : proseLines(root / document)) {
      const std::string t = trimLeft(line);
      if (startsWith(t, "#")) commandInSection = false;
      if (isCommandLine(t)) commandInSection = true;
      const bool tableLine = startsWith(t, "|");
      if (tableLine && !inTable && !commandInSection)
        problems.push_back(document.string() + ":" + std::to_string(number));
      inTable = tableLine;
    }
  }
  return problems;
}

// A shell line split into its commands at &&, ; and | outside quotes.
std::vector<std::string> splitCommands(const std::string& line) {
  std::vector<std::string> parts(1);
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == ';' || c == '|' || (c == '&' && i + 1 < line.size() && line[i + 1] == '&')) {
      if (c != ';' && i + 1 < line.size() && line[i + 1] == c) ++i;  // && and ||
      parts.emplace_back();
      continue;
    }
    parts.back() += c;
  }
  return parts;
}

// The commands that `Command:` lines quote, with where they are: each code span, split into its
// commands.
std::vector<std::pair<std::string, std::string>> quotedCommands(const fs::path& root) {
  std::vector<std::pair<std::string, std::string>> commands;
  for (const fs::path& document : documents(root))
    for (const auto& [number, line] : proseLines(root / document)) {
      if (!isCommandLine(line)) continue;
      for (const std::string& span : codeSpans(line))
        for (const std::string& part : splitCommands(span))
          if (!trimLeft(part).empty())
            commands.emplace_back(document.string() + ":" + std::to_string(number), trimLeft(part));
    }
  return commands;
}

std::vector<std::string> words(const std::string& command) {
  std::istringstream in(command);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// What is wrong with one quoted command, or "" when it names something that exists: a `kurage`
// (or build/kurage) subcommand whose --help succeeds, with its sub-subcommand when one follows
// (a bare lower-case word: `bench sim`, `farm status`); an executable script of the repository;
// or ctest. Leading VAR=value assignments are skipped.
std::string commandProblem(const fs::path& root, const fs::path& kurage, const std::string& command,
                           const fs::path& scratch, std::map<std::string, int>& helpStatus) {
  std::vector<std::string> w = words(command);
  while (!w.empty() && std::regex_match(w.front(), std::regex(R"re([A-Z_][A-Z0-9_]*=.*)re"))) w.erase(w.begin());
  if (w.empty()) return "an empty command";
  const std::string program = w.front();
  if (program == "ctest") return "";
  if (program == "kurage" || fs::path(program).filename() == "kurage") {
    if (w.size() < 2 || startsWith(w[1], "-")) return "names no kurage subcommand";
    std::string help = w[1];
    if (w.size() >= 3 && std::regex_match(w[2], std::regex("[a-z][a-z-]*"))) help += " " + w[2];
    auto known = helpStatus.find(help);
    if (known == helpStatus.end()) {
      const fs::path log = scratch / "help.log";
      const std::string line = kurage.string() + " " + help + " --help > " + log.string() + " 2>&1";
      const int status = std::system(line.c_str());
      known = helpStatus.emplace(help, WIFEXITED(status) ? WEXITSTATUS(status) : -1).first;
    }
    return known->second == 0 ? "" : "`kurage " + help + " --help` fails";
  }
  if (program.find('/') != std::string::npos) {
    const fs::path script = root / program;
    if (!fs::is_regular_file(script)) return "no such script " + program;
    if ((fs::status(script).permissions() & fs::perms::owner_exec) == fs::perms::none)
      return program + " is not executable";
    return "";
  }
  return "a results command must be kurage SUB, a script of the repository or ctest";
}

std::vector<std::string> badCommands(const fs::path& root, const fs::path& kurage, const fs::path& scratch) {
  std::vector<std::string> problems;
  std::map<std::string, int> helpStatus;  // each subcommand's --help is run once
  for (const auto& [where, command] : quotedCommands(root)) {
    const std::string problem = commandProblem(root, kurage, command, scratch, helpStatus);
    if (!problem.empty()) problems.push_back(where + ": " + command + " (" + problem + ")");
  }
  return problems;
}

// Dates (YYYY-MM-DD) and issue numbers on the user's and the design pages: "FILE:LINE: TEXT".
std::vector<std::string> history(const fs::path& root) {
  static const std::regex mark(R"re(\b20\d\d-\d\d-\d\d\b|\b[Ii]ssues? #?\d+)re");
  std::vector<std::string> problems;
  for (const fs::path& document : documents(root)) {
    const std::string name = document.generic_string();
    if (name != "README.md" && !startsWith(name, "docs/guide/") && !startsWith(name, "docs/design/")) continue;
    for (const auto& [number, rawLine] : proseLines(root / document)) {
      // A link to a dated notebook entry is what these pages should have: targets are not text.
      static const std::regex target(R"re(\]\([^)]*\))re");
      const std::string line = std::regex_replace(rawLine, target, "]");
      std::smatch m;
      if (std::regex_search(line, m, mark)) problems.push_back(name + ":" + std::to_string(number) + ": " + m.str());
    }
  }
  return problems;
}

std::string join(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += "  " + l + "\n";
  return out;
}

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

// A small documentation tree with one of each fault (and one correct instance of each).
fs::path brokenTree(const fs::path& dir) {
  write(dir / "README.md",
        "# Title\n\n[guide](docs/guide/cli.md) [gone](docs/gone.md) [anchor](docs/guide/cli.md#options)\n"
        "[bad anchor](docs/guide/cli.md#nowhere) ![figure](docs/figures/missing.png) [up](../outside.md)\n"
        "```\n[in a fence](not/checked.md)\n```\n`[in code](not/checked.md)` [web](https://example.org/x)\n"
        "Made on 2026-11-28 for issue 13.\n[a dated entry](docs/notebook/x.md#2026-11-27)\n");
  write(dir / "docs/guide/cli.md", "# The command line\n\n## Options\n\n[back](../../README.md#title)\n");
  write(dir / "docs/results/speed.md",
        "# Speed\n\nCommand: `kurage bench sim --json`\n\n| a | b |\n| --- | --- |\n\n## Later\n\n"
        "| c | d |\n| --- | --- |\n\nCommand: `kurage bench nosuch`, `kurage nosuch --json`, "
        "`scenes/missing.sh`, `python3 x.py`, `ctest -R \"A|B\" -V`, `X=1 kurage schema`\n");
  return dir;
}

}  // namespace

TEST(Docs, EveryRelativeLinkAndImageResolves) {
  const std::vector<std::string> problems = brokenLinks(test::sourceDir());
  EXPECT_TRUE(problems.empty()) << "links that do not resolve:\n" << join(problems);
}

TEST(Docs, EveryResultsTableSitsUnderTheCommandThatRegeneratesIt) {
  const std::vector<std::string> problems = tablesWithoutCommand(test::sourceDir());
  EXPECT_TRUE(problems.empty()) << "tables in docs/results/ with no `Command:` line in their section:\n"
                                << join(problems);
}

TEST(Docs, EveryQuotedCommandNamesASubcommandThatExists) {
  test::TempDir scratch;
  const auto commands = quotedCommands(test::sourceDir());
  EXPECT_GT(commands.size(), 10u) << "the results pages quote their commands on `Command:` lines";
  const std::vector<std::string> problems =
      badCommands(test::sourceDir(), test::binaryDir() / "kurage", scratch.path());
  EXPECT_TRUE(problems.empty()) << "commands that name nothing that exists:\n" << join(problems);
}

TEST(Docs, UserAndDesignPagesCarryNoHistory) {
  const std::vector<std::string> problems = history(test::sourceDir());
  EXPECT_TRUE(problems.empty()) << "dates and issue numbers belong in docs/notebook/:\n" << join(problems);
}

TEST(Docs, TheReadmeStaysShort) {
  EXPECT_LE(readLines(test::sourceDir() / "README.md").size(), 260u)
      << "README.md is the user's page; the rest belongs in docs/ (docs/README.md)";
}

TEST(Docs, EachCheckFindsItsFaultInABrokenTree) {
  test::TempDir dir;
  const fs::path root = brokenTree(dir.path() / "repo");
  const fs::path scratch = dir.path();

  const std::string links = join(brokenLinks(root));
  EXPECT_NE(links.find("docs/gone.md (no such file)"), std::string::npos) << links;
  EXPECT_NE(links.find("docs/guide/cli.md#nowhere (no such heading)"), std::string::npos) << links;
  EXPECT_NE(links.find("docs/figures/missing.png (no such file)"), std::string::npos) << links;
  EXPECT_NE(links.find("../outside.md (outside the repository)"), std::string::npos) << links;
  EXPECT_EQ(links.find("#options"), std::string::npos) << links;
  EXPECT_EQ(links.find("#title"), std::string::npos) << links;
  EXPECT_EQ(links.find("not/checked.md"), std::string::npos) << links;
  EXPECT_EQ(links.find("example.org"), std::string::npos) << links;

  const std::vector<std::string> tables = tablesWithoutCommand(root);
  ASSERT_EQ(tables.size(), 1u) << join(tables);
  EXPECT_EQ(tables[0], "docs/results/speed.md:10");

  const std::string commands = join(badCommands(root, test::binaryDir() / "kurage", scratch));
  EXPECT_NE(commands.find("`kurage bench nosuch --help` fails"), std::string::npos) << commands;
  EXPECT_NE(commands.find("`kurage nosuch --help` fails"), std::string::npos) << commands;
  EXPECT_NE(commands.find("no such script scenes/missing.sh"), std::string::npos) << commands;
  EXPECT_NE(commands.find("python3 x.py (a results command"), std::string::npos) << commands;
  EXPECT_EQ(commands.find("bench sim --json"), std::string::npos) << commands;
  EXPECT_EQ(commands.find("B\""), std::string::npos) << "a quoted | splits nothing: " << commands;
  EXPECT_EQ(commands.find("schema"), std::string::npos) << commands;

  const std::string dated = join(history(root));
  EXPECT_NE(dated.find("README.md:9: 2026-11-28"), std::string::npos) << dated;
  EXPECT_EQ(dated.find("README.md:10"), std::string::npos) << "a link's target is not text: " << dated;
}
