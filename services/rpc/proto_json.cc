#include "services/rpc/proto_json.h"

#include <google/protobuf/util/json_util.h>

namespace gaitforge::rpc {

std::string ToJson(const google::protobuf::Message& m) {
  std::string out;
  google::protobuf::util::JsonPrintOptions o;
  o.preserve_proto_field_names = true;
  o.always_print_primitive_fields = true;
  (void)google::protobuf::util::MessageToJsonString(m, &out, o);
  return out;
}

}  // namespace gaitforge::rpc
