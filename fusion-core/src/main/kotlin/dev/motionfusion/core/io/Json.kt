/*
 * A small JSON reader and writer for metadata files (meta.json): objects as LinkedHashMap
 * (key order kept), arrays as List, numbers as Long when integral without exponent or point,
 * else Double; strings, booleans, null. Strict RFC 8259 syntax; malformed input throws
 * DataFormatException with line and column. Numbers are written locale-independently.
 * [Json.document] keeps where each object member and array element starts, so that a member of
 * the wrong type is reported at its FILE:LINE:COLUMN ([JsonObject], the typed accessor of every
 * JSON file the project reads: meta.json, calibration files).
 */
package dev.motionfusion.core.io

import java.util.IdentityHashMap

internal object Json {
    private const val MAX_DEPTH = 64

    fun parse(text: String, sourceName: String): Any? = document(text, sourceName).root

    /** Parses [text] keeping the positions of its members and elements. */
    fun document(text: String, sourceName: String): JsonDocument {
        val p = Parser(text, sourceName)
        if (text.startsWith(BOM)) p.i = 1 // a UTF-8 byte order mark, as some editors save
        p.skipSpace()
        val v = p.value(0)
        p.skipSpace()
        if (p.i != text.length) throw p.error("unexpected '${text[p.i]}' after the JSON value")
        return JsonDocument(v, text, sourceName, p.memberStarts, p.elementStarts, p.containerStarts)
    }

    /**
     * True when [text] is not JSON only because it ends too early (a file cut short by a full
     * disk or a lost write, possibly followed by zero bytes): its parse fails at its end. False
     * for valid JSON and for any other fault (a wrong character, nesting deeper than the limit).
     */
    fun endsEarly(text: String): Boolean {
        val cut = text.trimEnd('\u0000', ' ', '\n', '\r', '\t')
        val p = Parser(cut, "")
        if (cut.startsWith(BOM)) p.i = 1
        return try {
            p.skipSpace()
            p.value(0)
            false
        } catch (e: DataFormatException) {
            p.i >= cut.length && !p.tooDeep
        }
    }

    private const val BOM = "\uFEFF"

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
        val memberStarts = IdentityHashMap<Map<*, *>, HashMap<String, Int>>()
        val elementStarts = IdentityHashMap<List<*>, IntArray>()
        val containerStarts = IdentityHashMap<Any, Int>()
        var tooDeep = false

        fun error(reason: String): DataFormatException = errorAt(s, i, source, reason)

        fun skipSpace() {
            while (i < s.length && (s[i] == ' ' || s[i] == '\n' || s[i] == '\r' || s[i] == '\t')) i++
        }

        fun value(depth: Int): Any? {
            if (depth > MAX_DEPTH) {
                tooDeep = true
                throw error("nested deeper than $MAX_DEPTH levels")
            }
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
            if (!s.startsWith(word, i)) {
                if (word.startsWith(s.substring(i))) i = s.length // cut inside the word
                throw error("expected '$word'")
            }
            i += word.length
            return v
        }

        private fun obj(depth: Int): Map<String, Any?> {
            val m = LinkedHashMap<String, Any?>()
            val starts = HashMap<String, Int>()
            memberStarts[m] = starts
            containerStarts[m] = i
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
                starts[k] = i
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
            val starts = ArrayList<Int>()
            containerStarts[a] = i
            i++
            skipSpace()
            if (i < s.length && s[i] == ']') { i++; return a }
            while (true) {
                skipSpace()
                starts.add(i)
                a.add(value(depth + 1))
                skipSpace()
                if (i >= s.length) throw error("unexpected end of file in an array")
                when (s[i]) {
                    ',' -> i++
                    ']' -> { i++; elementStarts[a] = starts.toIntArray(); return a }
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
                                if (i + 4 > s.length) {
                                    i = s.length
                                    throw error("short \\u escape")
                                }
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

/** A DataFormatException at character [offset] of [text] (line and column counted from 1). */
private fun errorAt(text: String, offset: Int, source: String, reason: String): DataFormatException {
    var line = 1L
    var lineStart = 0
    for (k in 0 until minOf(offset, text.length)) if (text[k] == '\n') { line++; lineStart = k + 1 }
    return DataFormatException(source, line, offset - lineStart + 1, reason)
}

/** A parsed JSON text ([root]) that knows where each member and element of it starts. */
internal class JsonDocument(
    val root: Any?,
    private val text: String,
    val sourceName: String,
    private val memberStarts: IdentityHashMap<Map<*, *>, HashMap<String, Int>>,
    private val elementStarts: IdentityHashMap<List<*>, IntArray>,
    private val containerStarts: IdentityHashMap<Any, Int>,
) {
    /** The root object, or an error at 1:1 when the root is not an object. */
    fun rootObject(): JsonObject =
        (root as? Map<*, *>)?.let { JsonObject(it, "", this) } ?: throw DataFormatException(sourceName, 1, 1, "expected a JSON object")

    /** An error at member [key] of [container] (a map), element [key] of a list, or the container itself when absent. */
    fun error(container: Any, key: Any?, reason: String): DataFormatException {
        val offset = when {
            container is Map<*, *> && key is String -> memberStarts[container]?.get(key)
            container is List<*> && key is Int -> elementStarts[container]?.getOrNull(key)
            else -> null
        } ?: containerStarts[container] ?: 0
        return errorAt(text, offset, sourceName, reason)
    }
}

/**
 * Typed access to one JSON object of a [JsonDocument]; errors name the member's path
 * ("sensors[2].type") and its FILE:LINE:COLUMN. An absent member is its default; a member of
 * the wrong type is an error.
 */
internal class JsonObject(val map: Map<*, *>, val path: String, val doc: JsonDocument) {
    /** An error at member [key] (at this object when the member is absent). */
    fun error(key: String, reason: String): DataFormatException = doc.error(map, key, "$path$key: $reason")

    fun keys(): List<String> = map.keys.map { it.toString() }
    fun raw(key: String): Any? = map[key]

    fun string(key: String): String = stringOrNull(key) ?: ""

    fun stringOrNull(key: String): String? = when (val v = raw(key)) {
        null -> null
        is String -> v
        else -> throw error(key, "expected a string")
    }

    fun longOrNull(key: String): Long? = when (val v = raw(key)) {
        null -> null
        is Long -> v
        is Double -> if (v == Math.rint(v) && kotlin.math.abs(v) < 9e18) v.toLong() else throw error(key, "expected an integer")
        else -> throw error(key, "expected an integer")
    }

    fun long(key: String, default: Long): Long = longOrNull(key) ?: default

    fun int(key: String, default: Int): Int {
        val v = longOrNull(key) ?: return default
        if (v < Int.MIN_VALUE || v > Int.MAX_VALUE) throw error(key, "integer out of range")
        return v.toInt()
    }

    fun double(key: String, default: Double = Double.NaN): Double = when (val v = raw(key)) {
        null -> default
        is Long -> v.toDouble()
        is Double -> v
        else -> throw error(key, "expected a number")
    }

    fun bool(key: String, default: Boolean): Boolean = when (val v = raw(key)) {
        null -> default
        is Boolean -> v
        else -> throw error(key, "expected true or false")
    }

    fun objOrNull(key: String): JsonObject? = when (val v = raw(key)) {
        null -> null
        is Map<*, *> -> JsonObject(v, "$path$key.", doc)
        else -> throw error(key, "expected an object")
    }

    fun obj(key: String): JsonObject = objOrNull(key) ?: JsonObject(emptyMap<String, Any>(), "$path$key.", doc)

    fun list(key: String): List<JsonObject> = when (val v = raw(key)) {
        null -> emptyList()
        is List<*> -> v.mapIndexed { i, x ->
            (x as? Map<*, *>)?.let { JsonObject(it, "$path$key[$i].", doc) } ?: throw doc.error(v, i, "$path$key[$i]: expected an object")
        }
        else -> throw error(key, "expected an array")
    }

    /** Member [key], an array of strings (absent: empty). */
    fun strings(key: String): List<String> = when (val v = raw(key)) {
        null -> emptyList()
        is List<*> -> v.mapIndexed { i, x -> x as? String ?: throw doc.error(v, i, "$path$key[$i]: expected a string") }
        else -> throw error(key, "expected an array")
    }

    /** Member [key], an array, as [n] finite numbers. */
    fun numbers(key: String, n: Int): DoubleArray = numbersOf(raw(key), n, key) { error(key, it) }

    /** Element [i] of the array member [key] as [n] finite numbers (a row of a matrix). */
    fun numbers(key: String, i: Int, n: Int): DoubleArray {
        val outer = raw(key) as? List<*> ?: throw error(key, "expected an array")
        return numbersOf(outer.getOrNull(i), n, "$key[$i]") { doc.error(outer, i, "$path$key[$i]: $it") }
    }

    private inline fun numbersOf(value: Any?, n: Int, name: String, fail: (String) -> DataFormatException): DoubleArray {
        val list = value as? List<*> ?: throw fail("expected an array of $n numbers")
        if (list.size != n) throw fail("expected $n numbers, got ${list.size}")
        return DoubleArray(n) { i ->
            (list[i] as? Number)?.toDouble()?.takeIf { it.isFinite() } ?: throw doc.error(list, i, "$path$name: element $i is not a finite number")
        }
    }
}
