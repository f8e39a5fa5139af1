#pragma once
// The API's messages as JSON, one way for every reader: the .proto's field names, zero
// values printed (proto3 JSON: int64 as strings, NaN and infinities as strings). What
// `gaitforge --json` prints and what the dashboard's endpoints answer.
#include <google/protobuf/message.h>

#include <string>

namespace gaitforge::rpc {

std::string ToJson(const google::protobuf::Message& m);

}  // namespace gaitforge::rpc
