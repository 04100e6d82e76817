// The registry of the `terroir` program (Applications/Commands/TerroirCommands.h) against the
// command-line parser's list (TerroirCommandLine.h): a command the parser accepts but the
// program cannot run, or code no command line reaches, fails here instead of at a user's prompt.
#include "TerroirApp.h"
#include "TerroirBenchPrivate.h"
#include "TerroirCommandLine.h"
#include "TerroirCommands.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>
#include <vector>

using namespace terroir::app;

namespace
{
/// The commands of Documentation/CLI.md's table: the rows "| `terroir NAME ...` | ... |" of
/// its first table.
std::set<std::string> DocumentedCommands()
{
  std::ifstream doc(std::string(TERROIR_SOURCE_DIR) + "/Documentation/CLI.md");
  EXPECT_TRUE(doc.good()) << "Documentation/CLI.md";
  std::set<std::string> names;
  std::string line;
  bool inTable = false;
  while (std::getline(doc, line))
  {
    if (line.rfind("| command |", 0) == 0)
    {
      inTable = true;
    }
    else if (inTable && line.rfind("| `terroir ", 0) == 0)
    {
      const std::size_t start = std::string("| `terroir ").size();
      const std::size_t end = line.find_first_of(" `", start);
      names.insert(line.substr(start, end - start));
    }
    else if (inTable && line.rfind("|", 0) != 0)
    {
      break;
    }
  }
  return names;
}
} // namespace

TEST(CommandRegistry, EveryParsedCommandRunsAndNoOther)
{
  std::vector<std::string> parsed, registered;
  for (const CommandDescription& info : CommandDescriptions())
  {
    parsed.emplace_back(info.Name);
  }
  for (const Command& command : Commands())
  {
    registered.emplace_back(command.Name);
    EXPECT_NE(command.Run, nullptr) << command.Name;
  }
  EXPECT_EQ(parsed, registered); // same names, in the order --help lists them
  EXPECT_EQ(std::set<std::string>(parsed.begin(), parsed.end()).size(), parsed.size());
  // Every command has its row in CLI.md's table of commands, and no row names another.
  EXPECT_EQ(std::set<std::string>(parsed.begin(), parsed.end()), DocumentedCommands());
  EXPECT_GE(parsed.size(), 15u); // run .. fractal: none disappears unnoticed
}

TEST(CommandRegistry, EveryCommandParsesItsHelp)
{
  for (const CommandDescription& info : CommandDescriptions())
  {
    const char* argv[] = { "terroir", info.Name, "--help" };
    CommandLine line;
    const ParseOutcome outcome = ParseCommandLine(3, argv, line);
    EXPECT_FALSE(outcome.Run) << info.Name;
    EXPECT_EQ(outcome.ExitCode, 0) << info.Name;
    EXPECT_NE(outcome.Stdout.find(info.Summary), std::string::npos) << info.Name;
  }
}

TEST(CommandRegistry, AnUnknownCommandIsAFailureNamingIt)
{
  CommandLine line;
  line.Command = "no-such-command";
  try
  {
    RunCommand(line);
    FAIL() << "no Failure";
  }
  catch (const Failure& e)
  {
    EXPECT_NE(std::string(e.what()).find("no-such-command"), std::string::npos) << e.what();
  }
}

TEST(CommandRegistry, EveryBenchStageTheParserAcceptsRunsAndNoOther)
{
  std::vector<std::string> registered;
  for (const BenchStage& stage : BenchStages())
  {
    registered.emplace_back(stage.Name);
    EXPECT_NE(stage.Run, nullptr) << stage.Name;
  }
  EXPECT_EQ(registered, BenchStageNames()); // same names, in the order `bench` runs them
  EXPECT_GE(registered.size(), 12u);        // slope .. kmeans: none disappears unnoticed
}
