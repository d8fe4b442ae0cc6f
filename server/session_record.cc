#include "server/session_record.h"

#include "bus/channels.h"
#include "bus/header.h"

namespace viscera::server {

namespace {

void Scrub(viscera_proto::header_t* header) {
  header->token.clear();
  header->token_len = 0;
  header->mac.clear();
  header->mac_len = 0;
}

}  // namespace

void ScrubbedRecord::WriteRequest(session::Recorder* recorder,
                                  const viscera_proto::session_request_t& request, int64_t utime) {
  if (recorder == nullptr) return;
  request_ = request;
  Scrub(&request_.header);
  recorder->Write(bus::kRequestChannel, request_, utime);
}

void ScrubbedRecord::WritePose(session::Recorder* recorder, const std::string& channel,
                               const viscera_proto::tool_pose_t& pose, int64_t utime) {
  if (recorder == nullptr) return;
  pose_ = pose;
  Scrub(&pose_.header);
  recorder->Write(channel, pose_, utime);
}

void ScrubbedRecord::WriteCreate(session::Recorder* recorder,
                                 const viscera_proto::session_request_t& request,
                                 int64_t session_id, const session::SessionScene& scene,
                                 int64_t utime) {
  if (recorder == nullptr) return;
  WriteRequest(recorder, request, utime);
  viscera_proto::session_request_t scene_record = request_;
  scene_record.header = bus::MakeHeader(session_id, 0);
  scene_record.scene_toml = scene.toml;
  scene_record.scene_name = scene.source;  // meshes resolve against it on replay
  scene_record.rate_hz = scene.model->params().rate_hz;
  recorder->Write(bus::SessionChannel(bus::kScenePrefix, session_id), scene_record, utime);
}

}  // namespace viscera::server
