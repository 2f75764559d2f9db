<?xml version="1.0" encoding="UTF-8"?>
<!--
  Part of target "shell" (included by shell.xsl): bin/start-host and bin/stop-host, which start and
  stop exactly the containers that one host runs, so that an application spread over machines is
  deployed by copying the built directory to each machine and running bin/start-host HOST there.

  HOST names a host as the model places containers (a container's host tag) or as the settings
  do (ACORDCS_<C>_HOST, which a user's line in env.sh or the environment may set to an address):
  a container runs on HOST when either is HOST. Each container's own script starts it, with its
  address, its port and the addresses of the containers it reaches (env.sh), and the token
  (ACORDCS_TOKEN or the run directory's token file: the same on every machine, see
  docs/deployment.md). Uses sh:quote, sh:header and $nl of shell.xsl.
-->
<xsl:stylesheet version="3.0"
    xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:d="http://acordcs.org/descriptor/1.0"
    xmlns:sh="http://acordcs.org/codegen/sh"
    exclude-result-prefixes="xs d sh">

  <!-- bin/start-host ($verb 'start') or bin/stop-host ($verb 'stop'). -->
  <xsl:template name="host-script">
    <xsl:param name="app" as="element(d:application)"/>
    <xsl:param name="verb" as="xs:string"/>
    <xsl:variable name="containers" select="$app/d:containers/d:container"/>
    <xsl:text>#!/bin/sh&#10;</xsl:text>
    <xsl:value-of select="sh:header('application ''' || $app/@name || '''',
        if ($verb = 'start')
        then 'Usage: start-host HOST [ARGUMENTS]. Starts the containers that run on HOST (the model''s host of a container, or its ACORDCS_&lt;C&gt;_HOST setting), in the model''s order, arguments going to each. Exit 0 when all started, 1 when one did not, 2 usage (HOST missing or no container runs there: the hosts are listed).'
        else 'Usage: stop-host HOST. Stops the containers that run on HOST (as start-host finds them), in the reverse order. Exit 0 when all stopped, 1 when one did not, 2 usage.')"/>
    <xsl:text><![CDATA[set -u
bin=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd) || exit 1
# shellcheck source=env.sh
. "$bin/env.sh"
# The hosts, for a usage message: each container with the model's host and its setting.
acordcs_hosts() {
]]></xsl:text>
    <xsl:for-each select="$containers">
      <xsl:value-of select="'    printf ''  %s: %s (setting ACORDCS_%s_HOST: %s)\n'' ' || sh:quote(@name) || ' ' || sh:quote(@host) || ' ' || sh:quote(@name) || ' &quot;$ACORDCS_' || @name || '_HOST&quot;' || $nl"/>
    </xsl:for-each>
    <xsl:text><![CDATA[}
if [ $# -lt 1 ] || [ -z "$1" ]; then
    printf '%s: usage: %s HOST%s; the containers and their hosts:\n' "${0##*/}" "${0##*/}" ]]></xsl:text>
    <xsl:value-of select="if ($verb = 'start') then ''' [ARGUMENTS]''' else ''''''"/>
    <xsl:text><![CDATA[ >&2
    acordcs_hosts >&2
    exit 2
fi
host=$1
shift
status=0
found=0
]]></xsl:text>
    <xsl:for-each select="if ($verb = 'start') then $containers else reverse($containers)">
      <xsl:value-of select="'if [ &quot;$host&quot; = ' || sh:quote(@host) || ' ] || [ &quot;$host&quot; = &quot;$ACORDCS_' || @name || '_HOST&quot; ]; then' || $nl"/>
      <xsl:value-of select="'    found=$((found + 1))' || $nl"/>
      <xsl:value-of select="'    sh &quot;$bin/' || @name || '-' || $verb || '&quot;' || (if ($verb = 'start') then ' &quot;$@&quot;' else '') || ' || status=1' || $nl"/>
      <xsl:text>fi&#10;</xsl:text>
    </xsl:for-each>
    <xsl:text><![CDATA[if [ "$found" = 0 ]; then
    printf '%s: no container runs on host %s; the containers and their hosts:\n' "${0##*/}" "$host" >&2
    acordcs_hosts >&2
    exit 2
fi
exit $status
]]></xsl:text>
  </xsl:template>
</xsl:stylesheet>
