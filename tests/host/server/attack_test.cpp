// The training centre under attack, at the API (both databases): results that cannot be forged
// onto a library case or graded from a cut record, lockouts that cannot be turned on an account's
// owner, the last admin kept, and trainees who cannot probe names or result ids.
#include <thread>

#include <gtest/gtest.h>

#include "server/live_hub.hpp"
#include "server/live_schema.hpp"
#include "server/live_service.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server {
namespace {

using test::error_of;
using test::FakeRecords;
using json = nlohmann::json;

class AttackTest : public test::CentreTest {
 protected:
  void SetUp() override {
    CentreTest::SetUp();
    ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  }
  std::string assign(const std::string& trainee) {
    const json a = f_->call_json("POST", "/api/v1/assignments", {{"trainee", trainee}, {"case", "ybif"}}, teacher_, 201);
    return "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>());
  }
  // A record of a case that is not the library's, its file named like the library case.
  static std::string forged(const std::string& file_stem) {
    json j = json::parse(FakeRecords::make("y_bifurcation", {{"target_reached", 1}}));
    j["case_file"] = file_stem + ".case";
    j["case"] = j["case"].get<std::string>() + "# target moved next to the start\n";
    return j.dump();
  }
};

TEST_P(AttackTest, AForeignCaseNamedLikeTheLibrarysIsNeitherFiledUnderItNorGraded) {
  const ApiResponse graded = f_->call("POST", assign("alice"), forged("ybif"), alice_);
  EXPECT_EQ(graded.status, 422) << graded.body;
  EXPECT_EQ(error_of(graded), "record: header field 'case_text' (ybif.case) is not the assignment's case 'ybif' version 1 (by content hash)");
  const ApiResponse kept = f_->call("POST", "/api/v1/results", forged("ybif"), alice_);
  ASSERT_EQ(kept.status, 201) << kept.body;
  EXPECT_EQ(json::parse(kept.body)["case"], "unlisted:ybif");
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results?case=ybif", nullptr, teacher_, 200)["results"].size(), 0U);
  // The library's own case still counts.
  const ApiResponse genuine = f_->call("POST", assign("alice"), FakeRecords::make("y_bifurcation", {{"target_reached", 1}}), alice_);
  EXPECT_EQ(genuine.status, 201) << genuine.body;
  EXPECT_EQ(json::parse(genuine.body)["case"], "ybif");
}

TEST_P(AttackTest, ACutRecordIsNeverGraded) {
  json cut = json::parse(FakeRecords::make("y_bifurcation", {{"target_reached", 1}}));
  cut["cut"] = true;
  const ApiResponse r = f_->call("POST", assign("alice"), cut.dump(), alice_);
  EXPECT_EQ(r.status, 422) << r.body;
  EXPECT_EQ(error_of(r).rfind("record: no end block", 0), 0U) << error_of(r);
}

TEST_P(AttackTest, TraineesCannotTellNamesOrResultIdsApart) {
  const ApiResponse mine = f_->call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {{"wall_contacts", 1}}), bob_);
  ASSERT_EQ(mine.status, 201) << mine.body;
  const std::string bobs = std::to_string(json::parse(mine.body)["id"].get<int>());
  const ApiResponse other = f_->call("GET", "/api/v1/results/" + bobs, "", alice_);
  const ApiResponse none = f_->call("GET", "/api/v1/results/9999", "", alice_);
  EXPECT_EQ(other.status, 404);
  EXPECT_EQ(other.status, none.status);
  EXPECT_EQ(error_of(other), "no result " + bobs);
  for (const std::string tail : {"/record", "/trace"}) {
    EXPECT_EQ(f_->call("GET", "/api/v1/results/" + bobs + tail, "", alice_).status, 404) << tail;
  }
  const ApiResponse existing = f_->call("GET", "/api/v1/results?trainee=bob", "", alice_);
  const ApiResponse unknown = f_->call("GET", "/api/v1/results?trainee=nobody", "", alice_);
  EXPECT_EQ(existing.status, 403);
  EXPECT_EQ(existing.status, unknown.status);
  EXPECT_EQ(error_of(existing), error_of(unknown));
  EXPECT_EQ(f_->call("GET", "/api/v1/results?trainee=alice", "", alice_).status, 200);
}

TEST_P(AttackTest, AnotherAddressGuessingDoesNotLockTheOwnerOutAndAResetUnlocks) {
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(f_->call("POST", "/api/v1/login", json{{"name", "alice"}, {"password", "wrong-one!"}}.dump(), "", "10.6.6.6").status, 401);
  }
  // The attacker's address is held back ...
  EXPECT_EQ(f_->call("POST", "/api/v1/login", json{{"name", "alice"}, {"password", "password-123"}}.dump(), "", "10.6.6.6").status, 429);
  // ... the owner, from hers, is not.
  EXPECT_EQ(f_->call("POST", "/api/v1/login", json{{"name", "alice"}, {"password", "password-123"}}.dump(), "", "10.0.0.7").status, 200);
  // An admin's password reset lifts the lockout from every address.
  EXPECT_EQ(f_->call("PATCH", "/api/v1/users/alice", json{{"password", "a-new-password"}}.dump(), admin_).status, 200);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", json{{"name", "alice"}, {"password", "a-new-password"}}.dump(), "", "10.6.6.6").status, 200);
  // So does enabling the account again (an admin's unlock).
  for (int i = 0; i < 5; ++i) (void)f_->call("POST", "/api/v1/login", json{{"name", "bob"}, {"password", "wrong-one!"}}.dump(), "", "10.0.0.9");
  EXPECT_EQ(f_->call("POST", "/api/v1/login", json{{"name", "bob"}, {"password", "password-123"}}.dump(), "", "10.0.0.9").status, 429);
  EXPECT_EQ(f_->call("PATCH", "/api/v1/users/bob", json{{"disabled", false}}.dump(), admin_).status, 200);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", json{{"name", "bob"}, {"password", "password-123"}}.dump(), "", "10.0.0.9").status, 200);
}

TEST_P(AttackTest, TwoAdminsDemotingEachOtherAtOnceLeaveOneAdmin) {
  // Rounds of two admins demoting each other on two threads: never none left.
  for (int round = 0; round < 20; ++round) {
    f_->clock.advance_us(60'000'000);  // the address's login bucket refills (virtual time)
    const std::string a = "admin-a" + std::to_string(round), b = "admin-b" + std::to_string(round);
    const std::string ta = f_->user(a, Role::kAdmin), tb = f_->user(b, Role::kAdmin);
    // Only these two are admins this round.
    for (const User& u : f_->store->list_users()) {
      if (u.role == Role::kAdmin && u.name != a && u.name != b) (void)f_->store->update_user(u.id, Role::kInstructor, std::nullopt, std::nullopt);
    }
    ApiResponse ra, rb;
    std::thread one([&] { ra = f_->call("PATCH", "/api/v1/users/" + b, json{{"role", "trainee"}}.dump(), ta); });
    std::thread two([&] { rb = f_->call("PATCH", "/api/v1/users/" + a, json{{"role", "trainee"}}.dump(), tb); });
    one.join();
    two.join();
    ASSERT_GE(f_->store->count_admins(), 1) << "round " << round << ": " << ra.status << " " << rb.status;
    // One demotion went through; the other was the last admin's (409) or came from an account no
    // longer an admin (403).
    EXPECT_FALSE(ra.status == 200 && rb.status == 200) << ra.status << " " << rb.status;
  }
}

// A subscriber that keeps what it is given (the hub calls deliver() under its lock: no blocking).
class Inbox final : public LiveSubscriber {
 public:
  void deliver(const LiveMessage& message) override { got.push_back(*message); }
  std::vector<std::string> got;
};

Caller caller_of(Store& store, const std::string& name) {
  const std::optional<User> u = store.user_by_name(name);
  return Caller{u->id, u->name, u->role, ""};
}

// A rig name is bound to the stream that opened it for the stream's whole life: a silent stream
// (no frame for a minute of the server's clock) keeps it; another account gets 409 until it ends.
TEST_P(AttackTest, ARigNameStaysWithItsOpenStreamHoweverSilent) {
  LiveService& live = f_->core->live();
  const Caller alice = caller_of(*f_->store, "alice"), bob = caller_of(*f_->store, "bob");
  Result<Publisher> first = live.start(alice, "rig-07", "ybif", 0, std::nullopt);
  ASSERT_TRUE(first) << first.error().message;
  f_->clock.advance_us(60'000'000);  // far past the store claim's 10 s staleness
  const Result<Publisher> hijack = live.start(bob, "rig-07", "ybif", 0, std::nullopt);
  ASSERT_FALSE(hijack);
  EXPECT_EQ(hijack.error().status, 409);
  EXPECT_EQ(hijack.error().message, "rig 'rig-07' is streaming for another user");
  // The same account reconnecting takes its rig again; the older stream's end then changes nothing.
  Result<Publisher> again = live.start(alice, "rig-07", "ybif", 0, std::nullopt);
  ASSERT_TRUE(again) << again.error().message;
  live.finish(first.value());
  EXPECT_FALSE(live.start(bob, "rig-07", "ybif", 0, std::nullopt));
  live.finish(again.value());
  EXPECT_TRUE(live.start(bob, "rig-07", "ybif", 0, std::nullopt));
}

// Across instances on one database the claim's age decides: the instance holding the open
// stream refreshes its claim on its sweep (keep_claims), frames or not, so another instance
// refuses the name for the stream's whole life; once that stream ends the name is free there.
TEST_P(AttackTest, ASilentStreamKeepsItsRigNameOnAnotherInstance) {
  LiveService& a = f_->core->live();
  LiveHub hub_b;  // instance B's own hub and bus
  LocalLiveBus bus(hub_b);
  LiveService b(*f_->store, f_->clock, bus, "instance-b");
  const Caller alice = caller_of(*f_->store, "alice"), bob = caller_of(*f_->store, "bob");
  Result<Publisher> stream = a.start(alice, "rig-07", "ybif", 0, std::nullopt);
  ASSERT_TRUE(stream) << stream.error().message;
  for (int second = 0; second < 60; ++second) {  // a silent minute, swept every second
    f_->clock.advance_us(1'000'000);
    a.keep_claims();
  }
  const Result<Publisher> hijack = b.start(bob, "rig-07", "ybif", 0, std::nullopt);
  ASSERT_FALSE(hijack);
  EXPECT_EQ(hijack.error().status, 409);
  // Without the sweep the claim goes stale after 10 s and the other instance hands the name out.
  f_->clock.advance_us(11'000'000);
  EXPECT_TRUE(b.start(bob, "rig-08", "ybif", 0, std::nullopt));
  Result<Publisher> stale = b.start(bob, "rig-07", "ybif", 0, std::nullopt);
  EXPECT_TRUE(stale) << "a claim not refreshed for 11 s is stale";
}

// A trainee's watch holds only while they stream the rig: rechecked when a stream starts on it
// and when it ends. An instructor's watch holds through both.
TEST_P(AttackTest, ATraineesWatchIsCheckedAgainWhenTheRigsStreamStartsAndEnds) {
  LiveService& live = f_->core->live();
  LiveHub& hub = f_->core->hub();
  const Caller alice = caller_of(*f_->store, "alice"), bob = caller_of(*f_->store, "bob");
  Result<Publisher> mine = live.start(alice, "rig-07", "ybif", 0, std::nullopt);
  ASSERT_TRUE(mine);
  ASSERT_TRUE(live.allowed(alice, {"rig-07"}));
  auto trainee = std::make_shared<Inbox>();
  auto teacher = std::make_shared<Inbox>();
  hub.subscribe("rig-07", trainee, "alice");
  hub.subscribe("rig-07", teacher);
  const auto frame = [&](const std::string& text) { hub.deliver_frame("rig-07", std::make_shared<const std::string>(text)); };
  frame("alice's frame");
  EXPECT_EQ(trainee->got.back(), "alice's frame");
  live.finish(mine.value());  // ended: alice no longer streams rig-07
  ASSERT_FALSE(trainee->got.empty());
  EXPECT_EQ(json::parse(trainee->got.back())["type"], "unwatched");
  ASSERT_TRUE(live.start(bob, "rig-07", "ybif", 0, std::nullopt));
  frame("bob's frame");
  EXPECT_NE(trainee->got.back(), "bob's frame");
  EXPECT_EQ(teacher->got.back(), "bob's frame");
  // Subscribed again while another trainee starts streaming the rig: dropped at that start.
  auto late = std::make_shared<Inbox>();
  hub.subscribe("rig-08", late, "alice");
  ASSERT_TRUE(live.start(bob, "rig-08", "ybif", 0, std::nullopt));
  EXPECT_EQ(json::parse(late->got.back())["type"], "unwatched");
  hub.deliver_frame("rig-08", std::make_shared<const std::string>("bob on 8"));
  EXPECT_NE(late->got.back(), "bob on 8");
}

TEST(AttackRouting, EverySpellingOfAnUploadIsClassifiedAsOne) {
  for (const char* t : {"/api/v1/results", "/api/v1//results", "/api//v1/results/", "//api/v1/results?assignment=1", "/api/v1/%72esults"}) {
    EXPECT_TRUE(Api::is_heavy("POST", t)) << t;
    EXPECT_EQ(Api::body_limit("POST", t), kMaxRecordBytes) << t;
  }
  EXPECT_TRUE(Api::is_heavy("POST", "/api/v1//cases"));
  EXPECT_TRUE(Api::is_heavy("GET", "/api/v1//results/3//trace"));
  EXPECT_FALSE(Api::is_heavy("GET", "/api/v1//me"));
  EXPECT_TRUE(Api::is_login("POST", "/api//v1/login"));
}

TEST(AttackLive, FramesWithUnknownFieldsAreRefusedNotRelayed) {
  const std::string junk(200'000, 'j');
  const Result<ParsedPublisherMessage> top = parse_publisher_message(R"({"type":"frame","seq":1,"t_ms":0,"junk":")" + junk + "\"}");
  ASSERT_FALSE(top);
  EXPECT_EQ(top.error().message, "frame: field 'junk': unknown field");
  const Result<ParsedPublisherMessage> tool =
      parse_publisher_message(R"({"type":"frame","seq":1,"t_ms":0,"tools":[{"name":"g","nodes_mm":[],"x":")" + junk + "\"}]}");
  ASSERT_FALSE(tool);
  EXPECT_EQ(tool.error().message, "frame: field 'tools[0].x': unknown field");
  const Result<ParsedPublisherMessage> contact =
      parse_publisher_message(R"({"type":"frame","seq":1,"t_ms":0,"contacts":[{"p_mm":[0,0,0],"f_mN":1,"x":1}]})");
  EXPECT_FALSE(contact);
  EXPECT_TRUE(parse_publisher_message(R"({"type":"frame","seq":1,"t_ms":0,"tools":[{"name":"g","active":true,"nodes_mm":[[0,0,0]]}]})"));
}

INSTANTIATE_TEST_SUITE_P(Backends, AttackTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
