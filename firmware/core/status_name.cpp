#include "core/status.hpp"

namespace fw {

const char* statusName(Status s) {
  switch (s) {
    case Status::Ok:
      return "Ok";
    case Status::Busy:
      return "Busy";
    case Status::InvalidArgument:
      return "InvalidArgument";
    case Status::Nack:
      return "Nack";
    case Status::DataNack:
      return "DataNack";
    case Status::Timeout:
      return "Timeout";
    case Status::ArbitrationLost:
      return "ArbitrationLost";
    case Status::BusStuck:
      return "BusStuck";
    case Status::Crc:
      return "Crc";
    case Status::Pec:
      return "Pec";
    case Status::Checksum:
      return "Checksum";
    case Status::Length:
      return "Length";
    case Status::EchoMismatch:
      return "EchoMismatch";
    case Status::Stale:
      return "Stale";
    case Status::Implausible:
      return "Implausible";
    case Status::DeviceId:
      return "DeviceId";
    case Status::Truncated:
      return "Truncated";
    case Status::NoResponse:
      return "NoResponse";
    case Status::CommFault:
      return "CommFault";
    case Status::Overflow:
      return "Overflow";
    case Status::BusOff:
      return "BusOff";
    case Status::NotReady:
      return "NotReady";
    case Status::VerifyFailed:
      return "VerifyFailed";
    case Status::Aborted:
      return "Aborted";
    case Status::Unsupported:
      return "Unsupported";
  }
  return "?";
}

}  // namespace fw
