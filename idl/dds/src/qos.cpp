#include "macsim/dds/qos.h"

#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <tinyxml2.h>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <string>

#include "macsim/dds/participant.h"

namespace macsim::dds {

namespace detail {
extern const char kQosFamiliesXml[];  // deploy/dds/qos.xml, embedded at build time
}  // namespace detail

namespace fdds = eprosima::fastdds::dds;

namespace {

/// Whether the loaded XML already defines a data writer or reader profile of this name.
bool defined(const std::string& element, const std::string& name) {
  namespace xml = eprosima::fastrtps::xmlparser;
  if (element == "data_writer") {
    eprosima::fastrtps::PublisherAttributes attributes;
    return xml::XMLProfileManager::fillPublisherAttributes(name, attributes, false) ==
           xml::XMLP_ret::XML_OK;
  }
  eprosima::fastrtps::SubscriberAttributes attributes;
  return xml::XMLProfileManager::fillSubscriberAttributes(name, attributes, false) ==
         xml::XMLP_ret::XML_OK;
}

}  // namespace

const char* profile_name(QosFamily family) {
  switch (family) {
    case QosFamily::Command:
      return "macsim_command";
    case QosFamily::Sensor:
      return "macsim_sensor";
    case QosFamily::State:
      return "macsim_state";
    case QosFamily::Latched:
      return "macsim_latched";
    case QosFamily::Request:
      return "macsim_request";
    case QosFamily::LockstepSensor:
      return "macsim_lockstep_sensor";
  }
  return "";
}

void load_builtin_qos_families() {
  tinyxml2::XMLDocument document;
  tinyxml2::XMLElement* profiles = nullptr;
  if (document.Parse(detail::kQosFamiliesXml) == tinyxml2::XML_SUCCESS && document.RootElement()) {
    profiles = document.RootElement()->FirstChildElement("profiles");
  }
  if (!profiles) throw DdsError("the built-in QoS families (deploy/dds/qos.xml) do not parse");
  // A profile of the same name loaded before (the deployment's) wins: Fast DDS refuses a
  // second profile of a name, so only the missing ones are loaded.
  bool missing = false;
  for (tinyxml2::XMLElement* profile = profiles->FirstChildElement(); profile;) {
    tinyxml2::XMLElement* next = profile->NextSiblingElement();
    const char* name = profile->Attribute("profile_name");
    if (name && defined(profile->Name(), name)) {
      profiles->DeleteChild(profile);
    } else {
      missing = true;
    }
    profile = next;
  }
  if (!missing) return;
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  if (fdds::DomainParticipantFactory::get_instance()->load_XML_profiles_string(
          printer.CStr(), static_cast<size_t>(printer.CStrSize() - 1)) !=
      ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot load the built-in QoS families (deploy/dds/qos.xml)");
  }
}

fdds::DataWriterQos writer_qos(QosFamily family, fdds::Publisher* publisher) {
  fdds::DataWriterQos qos;
  if (publisher->get_datawriter_qos_from_profile(profile_name(family), qos) !=
      ReturnCode_t::RETCODE_OK) {
    throw DdsError(std::string("no data writer profile '") + profile_name(family) +
                   "' loaded (a macsim::dds::Participant loads them)");
  }
  return qos;
}

fdds::DataReaderQos reader_qos(QosFamily family, fdds::Subscriber* subscriber) {
  fdds::DataReaderQos qos;
  if (subscriber->get_datareader_qos_from_profile(profile_name(family), qos) !=
      ReturnCode_t::RETCODE_OK) {
    throw DdsError(std::string("no data reader profile '") + profile_name(family) +
                   "' loaded (a macsim::dds::Participant loads them)");
  }
  return qos;
}

}  // namespace macsim::dds
