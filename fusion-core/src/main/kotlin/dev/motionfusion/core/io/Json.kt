/*
 * A small JSON reader and writer for metadata files (meta.json): objects as LinkedHashMap
 * (key order kept), arrays as List, numbers as Long when integral without exponent or point,
 * else Double; strings, booleans, null. Strict RFC 8259 syntax; malformed input throws
 * DataFormatException with line and column. Numbers are written locale-independently.
 */
package dev.motionfusion.core.io

internal object Json {
    private const val MAX_DEPTH = 64

    fun parse(text: String, sourceName: String): Any? {
        val p = Parser(text, sourceName)
        p.skipSpace()
        val v = p.value(0)
        p.skipSpace()
        if (p.i != text.length) throw p.error("unexpected '${text[p.i]}' after the JSON value")
        return v
    }

    fun write(value: Any?, indent: String = "  "): String = StringBuilder().also { write(it, value, indent, "") }.append('\n').toString()

    private fun write(sb: StringBuilder, v: Any?, indent: String, at: String) {
        when (v) {
            null -> sb.append("null")
            is String -> string(sb, v)
            is Boolean -> sb.append(v)
            is Int, is Long, is Short, is Byte -> sb.append(v.toString())
            is Float -> number(sb, v.toDouble())
            is Double -> number(sb, v)
            is Map<*, *> -> {
                if (v.isEmpty()) {
                    sb.append("{}")
                    return
                }
                sb.append("{\n")
                var first = true
                for ((k, x) in v) {
                    if (!first) sb.append(",\n")
                    first = false
                    sb.append(at).append(indent)
                    string(sb, k.toString())
                    sb.append(": ")
                    write(sb, x, indent, at + indent)
                }
                sb.append('\n').append(at).append('}')
            }
            is Iterable<*> -> {
                val items = v.toList()
                if (items.isEmpty()) {
                    sb.append("[]")
                    return
                }
                val simple = items.all { it !is Map<*, *> && it !is Iterable<*> }
                if (simple) {
                    sb.append('[')
                    items.forEachIndexed { n, x ->
                        if (n > 0) sb.append(", ")
                        write(sb, x, indent, at)
                    }
                    sb.append(']')
                    return
                }
                sb.append("[\n")
                items.forEachIndexed { n, x ->
                    if (n > 0) sb.append(",\n")
                    sb.append(at).append(indent)
                    write(sb, x, indent, at + indent)
                }
                sb.append('\n').append(at).append(']')
            }
            else -> string(sb, v.toString())
        }
    }

    /** Non-finite numbers have no JSON form: written as null. */
    private fun number(sb: StringBuilder, d: Double) {
        if (!d.isFinite()) sb.append("null") else sb.append(d.toString()) // Double.toString is locale-independent
    }

    private fun string(sb: StringBuilder, s: String) {
        sb.append('"')
        for (c in s) {
            when {
                c == '"' -> sb.append("\\\"")
                c == '\\' -> sb.append("\\\\")
                c == '\n' -> sb.append("\\n")
                c == '\r' -> sb.append("\\r")
                c == '\t' -> sb.append("\\t")
                c < ' ' -> sb.append("\\u").append(String.format(java.util.Locale.ROOT, "%04x", c.code))
                else -> sb.append(c)
            }
        }
        sb.append('"')
    }

    private class Parser(val s: String, val source: String) {
        var i = 0

        fun error(reason: String): DataFormatException {
            var line = 1L
            var lineStart = 0
            for (k in 0 until minOf(i, s.length)) if (s[k] == '\n') { line++; lineStart = k + 1 }
            return DataFormatException(source, line, i - lineStart + 1, reason)
        }

        fun skipSpace() {
            while (i < s.length && (s[i] == ' ' || s[i] == '\n' || s[i] == '\r' || s[i] == '\t')) i++
        }

        fun value(depth: Int): Any? {
            if (depth > MAX_DEPTH) throw error("nested deeper than $MAX_DEPTH levels")
            if (i >= s.length) throw error("unexpected end of file, expected a value")
            return when (val c = s[i]) {
                '{' -> obj(depth)
                '[' -> array(depth)
                '"' -> string()
                't' -> literal("true", true)
                'f' -> literal("false", false)
                'n' -> literal("null", null)
                else -> if (c == '-' || c in '0'..'9') number() else throw error("unexpected '$c', expected a value")
            }
        }

        private fun literal(word: String, v: Any?): Any? {
            if (!s.startsWith(word, i)) throw error("expected '$word'")
            i += word.length
            return v
        }

        private fun obj(depth: Int): Map<String, Any?> {
            val m = LinkedHashMap<String, Any?>()
            i++
            skipSpace()
            if (i < s.length && s[i] == '}') { i++; return m }
            while (true) {
                skipSpace()
                if (i >= s.length || s[i] != '"') throw error("expected a member name in quotes")
                val k = string()
                skipSpace()
                if (i >= s.length || s[i] != ':') throw error("expected ':' after member name")
                i++
                skipSpace()
                m[k] = value(depth + 1)
                skipSpace()
                if (i >= s.length) throw error("unexpected end of file in an object")
                when (s[i]) {
                    ',' -> i++
                    '}' -> { i++; return m }
                    else -> throw error("expected ',' or '}' in an object")
                }
            }
        }

        private fun array(depth: Int): List<Any?> {
            val a = ArrayList<Any?>()
            i++
            skipSpace()
            if (i < s.length && s[i] == ']') { i++; return a }
            while (true) {
                skipSpace()
                a.add(value(depth + 1))
                skipSpace()
                if (i >= s.length) throw error("unexpected end of file in an array")
                when (s[i]) {
                    ',' -> i++
                    ']' -> { i++; return a }
                    else -> throw error("expected ',' or ']' in an array")
                }
            }
        }

        private fun string(): String {
            val sb = StringBuilder()
            i++
            while (true) {
                if (i >= s.length) throw error("unterminated string")
                val c = s[i++]
                when {
                    c == '"' -> return sb.toString()
                    c == '\\' -> {
                        if (i >= s.length) throw error("unterminated escape")
                        when (val e = s[i++]) {
                            '"' -> sb.append('"'); '\\' -> sb.append('\\'); '/' -> sb.append('/')
                            'b' -> sb.append('\b'); 'f' -> sb.append('\u000c'); 'n' -> sb.append('\n')
                            'r' -> sb.append('\r'); 't' -> sb.append('\t')
                            'u' -> {
                                if (i + 4 > s.length) throw error("short \\u escape")
                                val h = s.substring(i, i + 4).toIntOrNull(16) ?: throw error("bad \\u escape")
                                sb.append(h.toChar())
                                i += 4
                            }
                            else -> { i--; throw error("bad escape '\\$e'") }
                        }
                    }
                    c < ' ' -> { i--; throw error("control character in a string") }
                    else -> sb.append(c)
                }
            }
        }

        private fun number(): Any {
            val start = i
            if (s[i] == '-') i++
            val intStart = i
            while (i < s.length && s[i] in '0'..'9') i++
            if (i == intStart) throw error("expected digits")
            if (s[intStart] == '0' && i - intStart > 1) { i = intStart; throw error("leading zero in a number") }
            var integral = true
            if (i < s.length && s[i] == '.') {
                integral = false
                i++
                val f = i
                while (i < s.length && s[i] in '0'..'9') i++
                if (i == f) throw error("expected digits after '.'")
            }
            if (i < s.length && (s[i] == 'e' || s[i] == 'E')) {
                integral = false
                i++
                if (i < s.length && (s[i] == '+' || s[i] == '-')) i++
                val f = i
                while (i < s.length && s[i] in '0'..'9') i++
                if (i == f) throw error("expected digits in the exponent")
            }
            val t = s.substring(start, i)
            if (integral) t.toLongOrNull()?.let { return it }
            return t.toDouble()
        }
    }
}
