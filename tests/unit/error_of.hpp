#pragma once
// Test helpers: the pr::Error a call throws, and substring checks on its message.
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <string>

namespace prtest {

template <typename F>
pr::Error error_of(F&& f)
{
    try {
        f();
    } catch (const pr::Error& e) {
        return e;
    }
    ADD_FAILURE() << "no pr::Error thrown";
    return pr::Error("(no error)", "(no error)");
}

inline bool contains(const std::string& s, const std::string& part)
{
    return s.find(part) != std::string::npos;
}

} // namespace prtest
