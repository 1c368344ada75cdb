#pragma once
// A fresh OSPRay device for a C API test, whose callbacks collect the messages the test
// then checks.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include <ospray/ospray.h>

namespace sciray_test {

struct Messages {
  std::vector<std::string> errors, status;
  std::vector<OSPError> codes;
  bool any_error_containing(const std::string& s) const { return any_containing(errors, s); }
  bool any_status_containing(const std::string& s) const { return any_containing(status, s); }

private:
  static bool any_containing(const std::vector<std::string>& list, const std::string& s) {
    for (const auto& e : list)
      if (e.find(s) != std::string::npos) return true;
    return false;
  }
};

struct ApiFixture {
  Messages messages;
  OSPDevice device;

  ApiFixture() {
    REQUIRE(ospInit() == OSP_NO_ERROR);
    device = ospGetCurrentDevice();
    ospDeviceSetErrorCallback(
        device,
        [](void* user, OSPError code, const char* text) {
          static_cast<Messages*>(user)->errors.emplace_back(text);
          static_cast<Messages*>(user)->codes.push_back(code);
        },
        &messages);
    ospDeviceSetStatusCallback(
        device, [](void* user, const char* text) { static_cast<Messages*>(user)->status.emplace_back(text); },
        &messages);
  }
  ~ApiFixture() {
    ospDeviceRelease(device);
    ospShutdown();
  }
  ApiFixture(const ApiFixture&) = delete;
  ApiFixture& operator=(const ApiFixture&) = delete;

  /// Checks that an error containing `fragment` was reported, then forgets the errors.
  void expect_error(const std::string& fragment) {
    INFO("expected an error containing: " << fragment);
    CHECK(messages.any_error_containing(fragment));
    messages.errors.clear();
  }
};

}  // namespace sciray_test
