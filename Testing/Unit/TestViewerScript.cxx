// The --script format of `terroir view` (Applications/TerroirViewerScript.h): every verb, and
// bad lines refused with "FILE:LINE: problem" before any window opens.
#include "TerroirViewerScript.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using terroir::viewer::ParseViewerScript;
using terroir::viewer::ViewerAction;

namespace
{
std::string ErrorOf(const std::string& script)
{
  std::vector<ViewerAction> actions;
  std::string error;
  EXPECT_FALSE(ParseViewerScript(script, "s.txt", 800, 600, actions, error)) << script;
  EXPECT_TRUE(actions.empty());
  return error;
}
} // namespace

TEST(TerroirViewerScript, ParsesEveryVerbWithItsArguments)
{
  const std::string script = "# a demo\n"
                             "overlay slope\n"
                             "\n"
                             "latitude 45   # comment\n"
                             "month 7\n"
                             "hour 15.5\n"
                             "click 10 20\n"
                             "drag 1 2 3 4 ctrl\n"
                             "wheel -2\n"
                             "key ctrl+z\n"
                             "tool lake\n"
                             "style first-person\n"
                             "wait\n"
                             "screenshot out/a.PNG\n"
                             "quit\n"
                             "button slope-rule\n"
                             "slope-threshold 25\n"
                             "state\n";
  std::vector<ViewerAction> a;
  std::string error;
  ASSERT_TRUE(ParseViewerScript(script, "s.txt", 800, 600, a, error)) << error;
  ASSERT_EQ(a.size(), 16u);
  EXPECT_EQ(a[0].Verb, "overlay");
  EXPECT_EQ(a[0].Text, "slope");
  EXPECT_EQ(a[0].Line, 2);
  EXPECT_EQ(a[1].Numbers, std::vector<double>{ 45.0 });
  EXPECT_EQ(a[1].Line, 4);
  EXPECT_EQ(a[3].Numbers, std::vector<double>{ 15.5 });
  EXPECT_EQ(a[4].Numbers, (std::vector<double>{ 10.0, 20.0 }));
  EXPECT_FALSE(a[4].Control);
  EXPECT_EQ(a[5].Numbers, (std::vector<double>{ 1.0, 2.0, 3.0, 4.0 }));
  EXPECT_TRUE(a[5].Control);
  EXPECT_EQ(a[6].Numbers, std::vector<double>{ -2.0 });
  EXPECT_EQ(a[7].Text, "z");
  EXPECT_TRUE(a[7].Control);
  EXPECT_EQ(a[8].Text, "lake");
  EXPECT_EQ(a[9].Text, "first-person");
  EXPECT_EQ(a[11].Text, "out/a.PNG");
  EXPECT_EQ(a[12].Verb, "quit");
  EXPECT_EQ(a[13].Verb, "button");
  EXPECT_EQ(a[13].Text, "slope-rule");
  EXPECT_EQ(a[14].Numbers, std::vector<double>{ 25.0 });
  EXPECT_EQ(a[15].Verb, "state");
}

TEST(TerroirViewerScript, BadLinesNameTheFileTheLineAndTheProblem)
{
  EXPECT_EQ(ErrorOf("wait\nfly 3\n"),
    "s.txt:2: unknown action 'fly' (overlay, latitude, longitude, month, hour, orientation, "
    "clusters, lake-depth, brush-size, brush-rate, slope-threshold, sensitivity, move-speed, "
    "style, tool, view, button, card, click, drag, wheel, key, flow, undo, wait, camera, state, "
    "screenshot, "
    "cluster-weight, table-csv, flow-mode, flow-iterations, flow-water, flow-rain-rate, "
    "flow-stop, flow-balance, sea, coldest, warmest, lapse-rate, precipitation, intensity, "
    "climate-load, climate-save, erosion, erosion-brush, erosion-amount, erosion-rain, "
    "wait-erosion, texture, quit)");
  EXPECT_EQ(ErrorOf("card map"), "s.txt:1: 'card': unknown value 'map' (none, climate, settings)");
  EXPECT_EQ(ErrorOf("erosion go"), "s.txt:1: 'erosion': unknown value 'go' (start, stop, keep)");
  EXPECT_EQ(ErrorOf("erosion-brush rock"),
    "s.txt:1: 'erosion-brush': unknown value 'rock' (soil, water, vegetation)");
  EXPECT_EQ(
    ErrorOf("wait-erosion 2.5"), "s.txt:1: 'wait-erosion': value 2.5 is not a whole number");
  EXPECT_EQ(
    ErrorOf("erosion-amount -200"), "s.txt:1: 'erosion-amount': value -200 is outside [-100, 100]");
  EXPECT_EQ(ErrorOf("move-speed 200"), "s.txt:1: 'move-speed': value 200 is outside [0.01, 100]");
  EXPECT_EQ(ErrorOf("button paint"),
    "s.txt:1: 'button': unknown value 'paint' (navigate, lake, brush, fill, slope-rule, flow, "
    "undo, table, climate, settings)");
  EXPECT_EQ(
    ErrorOf("slope-threshold 91"), "s.txt:1: 'slope-threshold': value 91 is outside [0, 90]");
  EXPECT_EQ(ErrorOf("state now"), "s.txt:1: 'state' takes no argument, got 1 argument");
  EXPECT_EQ(ErrorOf("overlay rivers"),
    "s.txt:1: unknown overlay 'rivers' (none, slope, illumination, sun-hours, temperature, "
    "humidity, water, clusters, weighted-humidity)");
  EXPECT_EQ(ErrorOf("latitude 91"), "s.txt:1: 'latitude': value 91 is outside [-90, 90]");
  EXPECT_EQ(ErrorOf("month 6.5"), "s.txt:1: 'month': value 6.5 is not a whole number");
  EXPECT_EQ(ErrorOf("hour nan"), "s.txt:1: 'hour': value 'nan' is not a finite number");
  EXPECT_EQ(ErrorOf("hour 1e400"), "s.txt:1: 'hour': value '1e400' is not a finite number");
  EXPECT_EQ(ErrorOf("hour"), "s.txt:1: 'hour' takes one number, got 0 arguments");
  EXPECT_EQ(ErrorOf("click 800 10"), "s.txt:1: 'click': x 800 is outside [0, 799]");
  EXPECT_EQ(ErrorOf("click 10 -1"), "s.txt:1: 'click': y -1 is outside [0, 599]");
  EXPECT_EQ(ErrorOf("click 10"), "s.txt:1: 'click' takes X Y [ctrl] [shift]");
  EXPECT_EQ(ErrorOf("drag 1 2 3 4 alt"), "s.txt:1: 'drag': unknown modifier 'alt' (ctrl or shift)");
  EXPECT_EQ(ErrorOf("wheel 0"), "s.txt:1: 'wheel': 0 notches does nothing");
  EXPECT_EQ(ErrorOf("key ctrl+"),
    "s.txt:1: unknown key 'ctrl+' (a character, or space, Return, Escape, Tab, Left, Right, Up, "
    "Down, F1..F12, with optional ctrl+ and shift+)");
  EXPECT_EQ(ErrorOf("screenshot a.jpg"), "s.txt:1: 'screenshot': 'a.jpg' does not end in .png");
  EXPECT_EQ(ErrorOf("quit now"), "s.txt:1: 'quit' takes no argument, got 1 argument");
  EXPECT_EQ(
    ErrorOf("tool pencil"), "s.txt:1: 'tool': unknown value 'pencil' (navigate, lake, brush, sea)");
  EXPECT_EQ(ErrorOf("cluster-weight rain 1"),
    "s.txt:1: 'cluster-weight': unknown feature 'rain' (slope, temperature, sun, humidity)");
  EXPECT_EQ(ErrorOf("cluster-weight slope -1"),
    "s.txt:1: 'cluster-weight': weight -1 is outside [0, 1000]");
  EXPECT_EQ(ErrorOf("cluster-weight slope"),
    "s.txt:1: 'cluster-weight' takes a feature (slope, temperature, sun, humidity) and a "
    "weight, got 1 argument");
  EXPECT_EQ(ErrorOf("table-csv t.txt"), "s.txt:1: 'table-csv': 't.txt' does not end in .csv");
  EXPECT_EQ(
    ErrorOf("flow-mode flood"), "s.txt:1: 'flow-mode': unknown value 'flood' (pulse, rivers)");
  EXPECT_EQ(
    ErrorOf("flow-iterations 2.5"), "s.txt:1: 'flow-iterations': value 2.5 is not a whole number");
  EXPECT_EQ(
    ErrorOf("flow-rain-rate 0"), "s.txt:1: 'flow-rain-rate': value 0 is outside [0.001, 1000]");
  EXPECT_EQ(ErrorOf("flow-stop 2"), "s.txt:1: 'flow-stop': value 2 is outside [0, 1]");
  EXPECT_EQ(
    ErrorOf("precipitation 13 50"), "s.txt:1: 'precipitation': month 13 is outside [1, 12]");
  EXPECT_EQ(ErrorOf("intensity 7 501"), "s.txt:1: 'intensity': value 501 is outside [0, 500]");
  EXPECT_EQ(ErrorOf("precipitation 7"),
    "s.txt:1: 'precipitation' takes a month 1..12 and millimetres, got 1 argument");
  EXPECT_EQ(ErrorOf("lapse-rate 21"), "s.txt:1: 'lapse-rate': value 21 is outside [0, 20]");
  EXPECT_EQ(
    ErrorOf("climate-load"), "s.txt:1: 'climate-load' takes one file name, got 0 arguments");
}

TEST(TerroirViewerScript, ParsesTheClusterVerbs)
{
  std::vector<ViewerAction> a;
  std::string error;
  ASSERT_TRUE(ParseViewerScript(
    "cluster-weight humidity 2.5\ntable-csv out/t.csv\n", "s.txt", 800, 600, a, error))
    << error;
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].Text, "humidity");
  EXPECT_EQ(a[0].Numbers, std::vector<double>{ 2.5 });
  EXPECT_EQ(terroir::viewer::ClusterFeatureIndex(a[0].Text), 3);
  EXPECT_EQ(a[1].Verb, "table-csv");
  EXPECT_EQ(a[1].Text, "out/t.csv");
}

TEST(TerroirViewerScript, UnreadableFilesAreOneLine)
{
  std::vector<ViewerAction> a;
  std::string error;
  EXPECT_FALSE(terroir::viewer::ReadViewerScript("/nonexistent/s.txt", 800, 600, a, error));
  EXPECT_EQ(error, "/nonexistent/s.txt: cannot read (No such file or directory)");
  EXPECT_FALSE(terroir::viewer::ReadViewerScript("/tmp", 800, 600, a, error));
  EXPECT_EQ(error, "/tmp: is a folder, not a script");
}
