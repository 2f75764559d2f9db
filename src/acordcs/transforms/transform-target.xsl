<?xml version="1.0" encoding="UTF-8"?>
<!--
  Runs one XSLT target of acordcs-gen (acordcs/generator/xslt.py): the target's stylesheet through
  fn:transform with the delivery format "serialized", over the descriptor given as the source: every
  output (the principal one under the base output URI) comes back as the string Saxon's serializer
  made of it, with the serialization parameters of its xsl:result-document; nothing is written by
  Saxon. The result is one string: each output's URI, then its text, each preceded by its length
  in characters and a colon. The target's xsl:messages reach this
  stylesheet's messages. "cache" is off: an edited stylesheet is compiled again.
-->
<xsl:stylesheet version="3.0"
    xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:map="http://www.w3.org/2005/xpath-functions/map">
  <xsl:param name="stylesheet" as="xs:string" required="yes"/>
  <xsl:param name="base" as="xs:string" required="yes"/>
  <xsl:param name="parameters" as="map(xs:string, xs:string)" required="yes"/>
  <xsl:template match="/">
    <xsl:variable name="outputs" as="map(*)" select="transform(map {
        'stylesheet-location': $stylesheet,
        'source-node': .,
        'delivery-format': 'serialized',
        'base-output-uri': $base,
        'cache': false(),
        'stylesheet-params': map:merge(map:for-each($parameters,
            function ($name, $value) { map { QName('', $name): $value } }))
      })"/>
    <!-- One string for all of them, each URI and text preceded by its length in characters and a
         colon: the build reads it in one call instead of two per file. -->
    <xsl:sequence select="string-join(map:keys($outputs) ! (
        let $text := string($outputs(.))
        return string-length(.) || ':' || . || string-length($text) || ':' || $text))"/>
  </xsl:template>
</xsl:stylesheet>
