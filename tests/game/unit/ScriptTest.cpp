// Script parsing and playback: the headless tests' input path.
#include <gtest/gtest.h>

#include "Input.h"
#include "Script.h"

using namespace marble;

TEST(Script, ParsesEventsCommentsAndSortsByTime) {
  const auto r = parseScript(
      "# a comment line\n"
      "\n"
      "1.20 up w   # release\n"
      "0.50 down W\n"
      "2 press 1\n"
      "2 mouse 120 -30.5\n"
      "3.0 scroll -2\n");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.events.size(), 5u);
  EXPECT_DOUBLE_EQ(r.events[0].time, 0.5);
  EXPECT_EQ(r.events[0].action, ScriptAction::Down);
  EXPECT_EQ(r.events[0].key, "W");
  EXPECT_EQ(r.events[0].line, 4);
  EXPECT_EQ(r.events[1].action, ScriptAction::Up);
  EXPECT_EQ(r.events[1].key, "W");  // lower case in the file, canonical here
  // Equal times keep file order.
  EXPECT_EQ(r.events[2].action, ScriptAction::Press);
  EXPECT_EQ(r.events[3].action, ScriptAction::Mouse);
  EXPECT_FLOAT_EQ(r.events[3].delta.x, 120.0f);
  EXPECT_FLOAT_EQ(r.events[3].delta.y, -30.5f);
  EXPECT_EQ(r.events[4].action, ScriptAction::Scroll);
  EXPECT_FLOAT_EQ(r.events[4].delta.x, -2.0f);
}

TEST(Script, ErrorsNameTheLineAndReason) {
  struct Case {
    const char* text;
    const char* expect;
  } cases[] = {
      {"0.5 down W\nabc down W\n", "line 2: expected a time"},
      {"-1 down W\n", "line 1: expected a time"},
      {"1.5abc down W\n", "line 1: expected a time"},
      {"1.0\n", "line 1: missing action"},
      {"1.0 hold W\n", "line 1: unknown action 'hold'"},
      {"1.0 down NOPE\n", "line 1: unknown key 'NOPE'"},
      {"1.0 down W S\n", "line 1: 'down' takes exactly one key"},
      {"1.0 mouse 3\n", "line 1: 'mouse' takes two numbers"},
      {"1.0 scroll x\n", "line 1: 'scroll' takes one number"},
      {"nan down W\n", "line 1: expected a time"},
  };
  for (const Case& c : cases) {
    const auto r = parseScript(c.text);
    EXPECT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.error.find(c.expect), std::string::npos) << "got: " << r.error << " for: " << c.text;
    EXPECT_TRUE(r.events.empty());
  }
}

TEST(Script, PlayerAppliesEventsWhenTimeIsReached) {
  const auto r = parseScript("0.5 down W\n0.5 press F1\n1.0 up W\n1.0 mouse 10 5\n1.0 mouse 1 1\n2.0 down W\n");
  ASSERT_TRUE(r.ok()) << r.error;
  ScriptPlayer player(r.events);
  InputState input;
  std::vector<std::string> edges;
  auto onDown = [&](const std::string& k) { edges.push_back(k); };

  player.advance(0.4999, input, onDown);
  EXPECT_FALSE(input.isDown("W"));
  EXPECT_TRUE(edges.empty());

  player.advance(0.5, input, onDown);
  EXPECT_TRUE(input.isDown("W"));
  EXPECT_FALSE(input.isDown("F1"));  // press is an edge, not a hold
  EXPECT_EQ(edges, (std::vector<std::string>{"W", "F1"}));

  player.advance(1.0, input, onDown);
  EXPECT_FALSE(input.isDown("W"));
  EXPECT_FLOAT_EQ(input.mouseDelta.x, 11.0f);
  EXPECT_FLOAT_EQ(input.mouseDelta.y, 6.0f);
  input.consumeDeltas();
  EXPECT_FLOAT_EQ(input.mouseDelta.x, 0.0f);
  EXPECT_FALSE(player.finished());

  player.advance(5.0, input, onDown);
  EXPECT_TRUE(input.isDown("W"));
  EXPECT_EQ(edges.size(), 3u);
  EXPECT_TRUE(player.finished());
}

TEST(Script, HeldKeyDownTwiceFiresOneEdge) {
  const auto r = parseScript("0 down A\n0.1 down A\n");
  ASSERT_TRUE(r.ok());
  ScriptPlayer player(r.events);
  InputState input;
  int edges = 0;
  player.advance(1.0, input, [&](const std::string&) { ++edges; });
  EXPECT_EQ(edges, 1);
}

TEST(Input, KeyNamesAndIntent) {
  EXPECT_EQ(canonicalKeyName("space"), "SPACE");
  EXPECT_EQ(canonicalKeyName("f12"), "F12");
  EXPECT_EQ(canonicalKeyName("q"), "Q");
  EXPECT_FALSE(canonicalKeyName("F13").has_value());
  EXPECT_FALSE(canonicalKeyName("").has_value());

  InputState in;
  in.held = {"W", "D"};
  MoveIntent m = moveIntent(in);
  EXPECT_FLOAT_EQ(m.move.x, 1.0f);
  EXPECT_FLOAT_EQ(m.move.y, 1.0f);
  in.held = {"UP", "DOWN", "LEFT", "SPACE", "Q"};
  m = moveIntent(in);
  EXPECT_FLOAT_EQ(m.move.y, 0.0f);  // opposite keys cancel
  EXPECT_FLOAT_EQ(m.move.x, -1.0f);
  EXPECT_TRUE(m.brake);
  EXPECT_FLOAT_EQ(m.orbit, -1.0f);
}
