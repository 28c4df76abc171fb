#!/usr/bin/env bash
# DDS Security for MACSim-DDS: a certificate authority, three identities and their Fast DDS
# profiles, the domain governance and the permissions, all signed by the CA.
#   macsim      the simulator (or kurt_adapter): every topic
#   operator    may use the supervisor (rt/macsim/supervisor/*) and everything else
#   controller  robot topics and simulation control, but not the supervisor
# Participants must authenticate (PKI-DH); access control decides who reads and writes which
# topic; the supervisor's topics are encrypted (AES-GCM). Give each program its identity's
# profile: FASTRTPS_DEFAULT_PROFILES_FILE=DIR/<identity>.xml (or --profile).
#   deploy/security/make_security.sh DIR [--localhost]   (--localhost: stay on 127.0.0.1 + SHM)
set -euo pipefail
umask 077  # keys are never readable by others, not even for a moment
if [[ $# -lt 1 || "$1" == "--help" ]]; then
  echo "usage: $0 DIR [--localhost]   writes ca.pem, <identity>.pem/.key/.xml, governance.p7s, permissions.p7s"
  [[ $# -ge 1 ]] && exit 0 || exit 2
fi
dir=$(mkdir -p "$1" && cd "$1" && pwd)
if [[ "$dir" =~ [[:space:]\&\<\>\"\'] ]]; then
  echo "make_security: DIR must not contain spaces or any of & < > \" ' (it goes into XML and URIs): $dir" >&2
  exit 2
fi
localhost=false
[[ "${2:-}" == "--localhost" ]] && localhost=true
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
cd "$dir"

# The CA, and one ECDSA P-256 identity per role, valid for ten years. Run again (e.g. after
# editing governance.xml or permissions.xml), the script keeps the CA and the identities it
# finds, so identities already deployed stay valid; it re-signs the XML and rewrites profiles.
if [[ ! -f ca.key ]]; then
  openssl ecparam -name prime256v1 -genkey -noout -out ca.key 2>/dev/null
  openssl req -new -x509 -key ca.key -out ca.pem -days 3650 -subj "/O=MACSim-DDS/CN=MACSim-DDS CA" \
    2>/dev/null
fi
for id in macsim operator controller; do
  [[ -f "$id.key" && -f "$id.pem" ]] && continue
  openssl ecparam -name prime256v1 -genkey -noout -out "$id.key" 2>/dev/null
  openssl req -new -key "$id.key" -out "$id.csr" -subj "/O=MACSim-DDS/CN=$id" 2>/dev/null
  openssl x509 -req -in "$id.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -out "$id.pem" \
    -days 3650 2>/dev/null
  rm "$id.csr"
done

# Governance and permissions, signed (S/MIME) by the CA, as the DDS Security plugins expect.
cp "$here/governance.xml" "$here/permissions.xml" .
openssl smime -sign -in governance.xml -text -out governance.p7s -signer ca.pem -inkey ca.key
openssl smime -sign -in permissions.xml -text -out permissions.p7s -signer ca.pem -inkey ca.key

# One Fast DDS profile per identity.
for id in macsim operator controller; do
  if $localhost; then
    transports='<transport_descriptor><transport_id>shm</transport_id><type>SHM</type><segment_size>8388608</segment_size></transport_descriptor>
      <transport_descriptor><transport_id>udp</transport_id><type>UDPv4</type><interfaceWhiteList><address>127.0.0.1</address></interfaceWhiteList></transport_descriptor>'
  else
    transports='<transport_descriptor><transport_id>shm</transport_id><type>SHM</type><segment_size>8388608</segment_size></transport_descriptor>
      <transport_descriptor><transport_id>udp</transport_id><type>UDPv4</type><sendBufferSize>4194304</sendBufferSize><receiveBufferSize>4194304</receiveBufferSize></transport_descriptor>'
  fi
  cat > "$id.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- MACSim-DDS secure participant '$id' (made by deploy/security/make_security.sh); the QoS
     families are the library's (deploy/dds/qos.xml). -->
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <transport_descriptors>
      $transports
    </transport_descriptors>
    <participant profile_name="macsim_secure_$id" is_default_profile="true">
      <rtps>
        <userTransports><transport_id>shm</transport_id><transport_id>udp</transport_id></userTransports>
        <useBuiltinTransports>false</useBuiltinTransports>
        <builtin><discovery_config>
          <leaseDuration><sec>5</sec></leaseDuration><leaseAnnouncement><sec>1</sec></leaseAnnouncement>
        </discovery_config></builtin>
        <propertiesPolicy><properties>
          <property><name>dds.sec.auth.plugin</name><value>builtin.PKI-DH</value></property>
          <property><name>dds.sec.auth.builtin.PKI-DH.identity_ca</name><value>file://$dir/ca.pem</value></property>
          <property><name>dds.sec.auth.builtin.PKI-DH.identity_certificate</name><value>file://$dir/$id.pem</value></property>
          <property><name>dds.sec.auth.builtin.PKI-DH.private_key</name><value>file://$dir/$id.key</value></property>
          <property><name>dds.sec.access.plugin</name><value>builtin.Access-Permissions</value></property>
          <property><name>dds.sec.access.builtin.Access-Permissions.permissions_ca</name><value>file://$dir/ca.pem</value></property>
          <property><name>dds.sec.access.builtin.Access-Permissions.governance</name><value>file://$dir/governance.p7s</value></property>
          <property><name>dds.sec.access.builtin.Access-Permissions.permissions</name><value>file://$dir/permissions.p7s</value></property>
          <property><name>dds.sec.crypto.plugin</name><value>builtin.AES-GCM-GMAC</value></property>
        </properties></propertiesPolicy>
      </rtps>
    </participant>
  </profiles>
</dds>
XML
done
chmod 644 ca.pem ./*.pem ./*.xml ./*.p7s  # only the keys stay private
echo "make_security: identities macsim, operator, controller in $dir"
