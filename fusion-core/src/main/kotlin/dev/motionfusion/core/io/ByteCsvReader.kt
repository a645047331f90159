/*
 * The one CSV tokenizer of every text input (sessions, plain tables, truth tables, phyphox,
 * Sensor Logger): a streaming reader of separated ASCII numbers straight from bytes, no String
 * per line, no Double.parseDouble on the common path. Fields may be quoted ("Time (s)"; a
 * doubled quote inside a quoted field is one quote, as in RFC 4180, but a field never spans
 * lines); a UTF-8 byte order mark before the first line is skipped. Memory is one buffer (64 KiB, grown
 * for long lines up to [maxLineBytes], beyond which the line is an error, never an
 * OutOfMemoryError). Error texts quote at most a short, escaped excerpt of a field.
 */
package dev.motionfusion.core.io

import java.io.Closeable
import java.io.InputStream

internal class ByteCsvReader(
    private val input: InputStream,
    val sourceName: String,
    private val separator: Byte = ','.code.toByte(),
    /** Numbers may use ',' as decimal mark (only with a separator other than ','). */
    private val decimalComma: Boolean = false,
    private val maxLineBytes: Int = MAX_LINE_BYTES,
    /** The bytes come out of a decompressor (gzip, a zip entry): an error in them may be damage that its check, at the end, would name. */
    private val compressed: Boolean = input is Decompressed,
) : Closeable {
    init {
        require(!(decimalComma && separator == COMMA)) { "a decimal comma needs another separator" }
    }

    private var buf = ByteArray(1 shl 16)

    /** [buf] read 8 bytes at a time (the digits of a plain row's fractions, see [digitRun]). */
    private var words = littleEndian(buf)
    private var pos = 0
    private var limit = 0
    private var eof = false

    private var lineStart = 0
    private var lineEnd = 0
    private var starts = IntArray(16)
    private var ends = IntArray(16)
    private var quoted = BooleanArray(16)

    /** 1-based number of the current line. */
    var lineNumber = 0L
        private set

    /** Fields in the current line. */
    var count = 0
        private set

    /**
     * Advances to the next line that is not empty; false at the end of the input. A final line
     * without a newline is returned too; [endedWithNewline] tells it apart.
     */
    fun nextLine(): Boolean {
        while (true) {
            if (!readLine()) return false
            if (lineEnd > lineStart) {
                split()
                return true
            }
        }
    }

    /** False when the current line was cut off by the end of the input (no final newline). */
    var endedWithNewline = true
        private set

    /** Fields of the header ([header]), which every data line must have. */
    private var headerFields = -1

    /**
     * Advances to the next data line and checks it has the header's field count; false at the
     * end. [skipCutLastLine]: a last line without its newline (a recording cut short) is the end.
     */
    fun nextRecord(skipCutLastLine: Boolean = false): Boolean {
        if (!nextLine()) return false
        if (skipCutLastLine && !endedWithNewline) return false
        requireFieldCount()
        return true
    }

    private fun readLine(): Boolean {
        var scan = pos
        while (true) {
            while (scan < limit) {
                if (buf[scan] == NL) {
                    lineNumber++
                    lineStart = pos
                    lineEnd = if (scan > pos && buf[scan - 1] == CR) scan - 1 else scan
                    pos = scan + 1
                    endedWithNewline = true
                    if (lineNumber == 1L) skipByteOrderMark()
                    return true
                }
                scan++
            }
            if (eof) {
                if (pos == limit) return false
                lineNumber++
                lineStart = pos
                lineEnd = if (buf[limit - 1] == CR) limit - 1 else limit
                pos = limit
                endedWithNewline = false
                if (lineNumber == 1L) skipByteOrderMark()
                return true
            }
            val scanned = scan - pos
            fill()
            scan = pos + scanned
        }
    }

    private fun skipByteOrderMark() {
        if (lineEnd - lineStart >= 3 && buf[lineStart] == 0xEF.toByte() && buf[lineStart + 1] == 0xBB.toByte() && buf[lineStart + 2] == 0xBF.toByte()) {
            lineStart += 3
        }
    }

    /** Moves unread bytes to the front (growing the buffer for a long line) and reads more. */
    private fun fill() {
        val unread = limit - pos
        if (pos > 0) {
            System.arraycopy(buf, pos, buf, 0, unread)
        } else if (unread == buf.size) {
            if (buf.size >= maxLineBytes) {
                // Not checked against the data's damage: sniffing a format meets this on every long first line.
                throw DataFormatException(sourceName, lineNumber + 1, 0, "line longer than $maxLineBytes bytes: not a CSV text file?")
            }
            buf = buf.copyOf(minOf(buf.size * 2, maxLineBytes))
            words = littleEndian(buf)
        }
        pos = 0
        limit = unread
        // Broken or oversized compressed data is reported by the stream (CompressionGuard).
        val n = input.read(buf, limit, buf.size - limit)
        if (n < 0) eof = true else limit += n
    }

    private fun split() {
        count = 0
        var i = lineStart
        var start = i
        var quotedEnd = -1
        if (i < lineEnd && buf[i] == QUOTE) quotedEnd = closingQuote(i)
        while (true) {
            if (i == lineEnd || (buf[i] == separator && i > quotedEnd)) {
                if (count == starts.size) {
                    starts = starts.copyOf(count * 2)
                    ends = ends.copyOf(count * 2)
                    quoted = quoted.copyOf(count * 2)
                }
                quoted[count] = quotedEnd >= 0
                if (quotedEnd >= 0) {
                    starts[count] = start + 1
                    ends[count] = quotedEnd
                } else {
                    starts[count] = start
                    ends[count] = i
                }
                count++
                if (i == lineEnd) return
                start = i + 1
                quotedEnd = if (start < lineEnd && buf[start] == QUOTE) closingQuote(start) else -1
            }
            i++
        }
    }

    /** The closing quote of the field opened at [open] (a doubled quote inside is part of the text), or the line end when there is none. */
    private fun closingQuote(open: Int): Int {
        var j = open + 1
        while (j < lineEnd) {
            if (buf[j] == QUOTE) {
                if (j + 1 < lineEnd && buf[j + 1] == QUOTE) j++ else return j
            }
            j++
        }
        return j
    }

    /**
     * Advances to the next line as [nextLine] does and, where it is a plain row of numbers,
     * parses it in the same pass over the bytes: [ROW] when the line has [fieldCount] fields,
     * each a plain decimal (optional sign, digits, optional fraction; at most 18 digits, at most
     * 22 of them after the point) or, where slot[i] < 0 (a field the caller ignores), any
     * unquoted text. Field i's value is then in out[slot[i]], exactly the double [parseDouble]
     * gives for it (the same single correctly rounded operation), and every other accessor
     * works as after [nextLine]. Any other line (quotes, spaces, exponents, NaN, empty fields,
     * a wrong field count, the header) gives [LINE]: it is split as by [nextLine] and nothing
     * is parsed, so the caller's general path reads it with its own rules and errors. [END] at
     * the end of the input.
     */
    fun nextRow(fieldCount: Int, slot: IntArray, out: DoubleArray): Int {
        if (starts.size < fieldCount) {
            starts = starts.copyOf(fieldCount)
            ends = ends.copyOf(fieldCount)
        }
        while (lineNumber > 0L) {
            val r = plainRow(fieldCount, slot, out)
            if (r != MORE) return r
            if (eof || (pos == 0 && limit == buf.size)) break // the last line, or a long one: the general path
            fill()
        }
        return if (nextLine()) LINE else END
    }

    /** [nextRow] within the bytes read so far: [MORE] when the line runs past them. */
    private fun plainRow(fieldCount: Int, slot: IntArray, out: DoubleArray): Int {
        val b = buf
        val lim = limit
        val start = pos
        var p = start
        var field = 0
        while (true) {
            if (p >= lim) return MORE
            val fieldStart = p
            var c = b[p].toInt()
            if (slot[field] < 0) {
                while (c != separator.toInt() && c != NL_INT && c != CR_INT) {
                    if (c == QUOTE.toInt()) return general()
                    if (++p >= lim) return MORE
                    c = b[p].toInt()
                }
            } else {
                var negative = false
                if (c == MINUS_INT || c == PLUS_INT) {
                    negative = c == MINUS_INT
                    if (++p >= lim) return MORE
                    c = b[p].toInt()
                }
                var m = 0L
                var digits = 0
                var fraction = 0
                while (c in ZERO_INT..NINE_INT) {
                    m = m * 10L + (c - ZERO_INT)
                    digits++
                    if (++p >= lim) return MORE
                    c = b[p].toInt()
                }
                if (c == DOT_INT || (decimalComma && c == COMMA_INT)) {
                    if (++p >= lim) return MORE
                    c = b[p].toInt()
                    // Up to 8 digits at a time while 8 bytes are left (the digits stay ≤ 18: m is exact).
                    while (p + 8 <= lim) {
                        val x = words.getLong(p) - ASCII_ZEROS
                        val n = digitRun(x)
                        if (n == 0 || digits + n > 18) break
                        m = m * LONG_POW10[n] + digitsValue(x, n)
                        digits += n
                        fraction += n
                        p += n
                        if (n < 8) break
                    }
                    if (p >= lim) return MORE
                    c = b[p].toInt()
                    while (c in ZERO_INT..NINE_INT) {
                        m = m * 10L + (c - ZERO_INT)
                        digits++
                        fraction++
                        if (++p >= lim) return MORE
                        c = b[p].toInt()
                    }
                }
                if (digits == 0 || digits > 18 || fraction > 22 || m >= EXACT_MANTISSA) return general()
                val v = if (fraction == 0) m.toDouble() else m.toDouble() / POW10[fraction]
                out[slot[field]] = if (negative) -v else v
            }
            starts[field] = fieldStart
            ends[field] = p
            field++
            if (c == separator.toInt()) {
                if (field == fieldCount) return general()
                p++
                continue
            }
            val end = p
            if (c == CR_INT) {
                if (++p >= lim) return MORE
                if (b[p] != NL) return general()
            } else if (c != NL_INT) {
                return general()
            }
            if (field != fieldCount || end == start) return general()
            lineNumber++
            lineStart = start
            lineEnd = end
            pos = p + 1
            count = field
            endedWithNewline = true
            return ROW
        }
    }

    private fun general(): Int = if (nextLine()) LINE else END

    /** The current line as text (headers, messages). */
    fun lineText(): String = String(buf, lineStart, lineEnd - lineStart, Charsets.UTF_8)

    /** Field [i] as text. */
    fun text(i: Int): String = String(buf, starts[i], ends[i] - starts[i], Charsets.UTF_8)

    /**
     * Field [i] as text, strictly decoded: a quoted field without its quotes and with each doubled
     * quote inside made one (RFC 4180). @throws FieldError when the bytes are not UTF-8.
     */
    fun unquotedText(i: Int): String {
        val decoder = Charsets.UTF_8.newDecoder()
            .onMalformedInput(java.nio.charset.CodingErrorAction.REPORT)
            .onUnmappableCharacter(java.nio.charset.CodingErrorAction.REPORT)
        val s = try {
            decoder.decode(java.nio.ByteBuffer.wrap(buf, starts[i], ends[i] - starts[i])).toString()
        } catch (e: java.nio.charset.CharacterCodingException) {
            throw FieldError("'${excerpt(i)}' is not UTF-8 text")
        }
        return if (quoted[i]) s.replace("\"\"", "\"") else s
    }

    /** 1-based character column of field [i] (counting UTF-8 characters, not bytes). */
    fun column(i: Int): Int = String(buf, lineStart, starts[i] - lineStart, Charsets.UTF_8).length + 1

    /** 1-based character column just after the end of the line. */
    fun endColumn(): Int = String(buf, lineStart, lineEnd - lineStart, Charsets.UTF_8).length + 1

    fun isEmpty(i: Int): Boolean = starts[i] == ends[i]

    /** Field [i] for messages: at most [EXCERPT_CHARS] characters, control characters and quotes escaped. */
    fun excerpt(i: Int): String = escapedExcerpt(String(buf, starts[i], minOf(ends[i] - starts[i], 4 * EXCERPT_CHARS), Charsets.UTF_8))

    /** A [DataFormatException] at field [i] of the current line. */
    fun error(i: Int, reason: String): DataFormatException = located(lineNumber, if (i < count) column(i) else endColumn(), reason)

    /**
     * The error at [line], [column] of the data, or, in compressed data, the damage that caused it: a flipped bit
     * in deflated data reads as garbage long before the CRC-32 at the end is checked, so up to [DAMAGE_CHECK_BYTES]
     * more are read first, and damage found there is the error, with the CSV error named as what it caused.
     */
    private fun located(line: Long, column: Int, reason: String): DataFormatException {
        val e = DataFormatException(sourceName, line, column, reason)
        if (!compressed) return e
        return try {
            // At most DAMAGE_CHECK_BYTES more (about a second): a damaged stream usually fails well before its end.
            val scratch = ByteArray(1 shl 16)
            var read = 0L
            while (read < DAMAGE_CHECK_BYTES) {
                val n = input.read(scratch)
                if (n < 0) break
                read += n
            }
            e
        } catch (damage: DataFormatException) {
            // The limits' own error is no damage: the CSV error stands.
            if (damage.cause is OverLimit) e
            else DataFormatException(damage.source, damage.line, damage.column, "${damage.reason} (damaged compressed data: it read as line $line, column $column: $reason)", damage)
        } catch (_: java.io.IOException) {
            e
        }
    }

    /**
     * Checks that the current line has [expected] fields (the header's count). A comma-separated
     * row with too many fields often holds decimal commas: the message says so.
     */
    fun requireFieldCount() {
        val expected = headerFields
        check(expected >= 0) { "no header read" }
        if (count == expected) return
        val hint = when {
            count > expected && separator == COMMA -> " (a decimal comma in a comma-separated file? numbers must use '.')"
            !endedWithNewline -> " (the last line, without an end of line: cut short when the recording stopped? delete it)"
            else -> ""
        }
        throw error(minOf(count, expected), "row has $count fields, the header has $expected$hint")
    }

    /** Field [i] as a time in seconds: finite, and within a nanosecond Long's range ([checkedTimeS]). */
    fun parseTimeS(i: Int): Double = checkedTimeS(parseDouble(i), i)

    /** [t], read from field [i], when it is a time in seconds a nanosecond Long can hold; else a FieldError. */
    fun checkedTimeS(t: Double, i: Int): Double {
        if (!(kotlin.math.abs(t) < MAX_TIME_S)) throw FieldError("time '${excerpt(i)}' is not a finite time (or beyond ±292 years)")
        return t
    }

    /** Field [i] as a decimal integer (optional sign, digits only). */
    fun parseLong(i: Int): Long {
        var p = starts[i]
        var e = ends[i]
        while (p < e && buf[p] == SPACE) p++
        while (e > p && buf[e - 1] == SPACE) e--
        if (p == e) throw FieldError("empty field, expected an integer")
        var negative = false
        if (buf[p] == MINUS || buf[p] == PLUS) {
            negative = buf[p] == MINUS
            p++
            if (p == e) throw FieldError("'${excerpt(i)}' is not an integer")
        }
        var v = 0L
        while (p < e) {
            val d = buf[p] - ZERO
            if (d !in 0..9) throw FieldError("'${excerpt(i)}' is not an integer")
            if (v > (Long.MAX_VALUE - d) / 10L) throw FieldError("'${excerpt(i)}' is out of range")
            v = v * 10L + d
            p++
        }
        return if (negative) -v else v
    }

    /**
     * Field [i] as a double: decimal notation with '.', optional exponent (e/E), NaN, Infinity.
     * Up to 18 significant digits with a small exponent are converted exactly by one correctly
     * rounded operation (the common case); anything else goes to Double.parseDouble after a
     * syntax check. Empty fields are NaN when [emptyIsNaN], else an error.
     */
    fun parseDouble(i: Int, emptyIsNaN: Boolean = false): Double {
        var p = starts[i]
        var e = ends[i]
        while (p < e && buf[p] == SPACE) p++
        while (e > p && buf[e - 1] == SPACE) e--
        if (p == e) {
            if (emptyIsNaN) return Double.NaN
            throw FieldError("empty field, expected a number")
        }
        val first = p
        var negative = false
        if (buf[p] == MINUS || buf[p] == PLUS) {
            negative = buf[p] == MINUS
            p++
        }
        var mantissa = 0L
        var digits = 0
        var sawDigit = false
        var exp10 = 0
        var exact = true
        while (p < e && buf[p] - ZERO in 0..9) {
            sawDigit = true
            if (digits < 18) {
                mantissa = mantissa * 10L + (buf[p] - ZERO)
                if (mantissa != 0L) digits++
            } else {
                exact = false
                exp10++
            }
            p++
        }
        if (p < e && (buf[p] == DOT || (decimalComma && buf[p] == COMMA))) {
            p++
            while (p < e && buf[p] - ZERO in 0..9) {
                sawDigit = true
                if (digits < 18) {
                    mantissa = mantissa * 10L + (buf[p] - ZERO)
                    if (mantissa != 0L) digits++
                    exp10--
                } else {
                    exact = false
                }
                p++
            }
        }
        if (!sawDigit) return special(first, e, i)
        if (p < e && (buf[p] == 'e'.code.toByte() || buf[p] == 'E'.code.toByte())) {
            p++
            var expNegative = false
            if (p < e && (buf[p] == MINUS || buf[p] == PLUS)) {
                expNegative = buf[p] == MINUS
                p++
            }
            if (p == e) throw FieldError("'${excerpt(i)}' is not a number")
            var x = 0
            while (p < e && buf[p] - ZERO in 0..9) {
                if (x < 100_000) x = x * 10 + (buf[p] - ZERO)
                p++
            }
            exp10 += if (expNegative) -x else x
        }
        if (p != e) throw FieldError("'${excerpt(i)}' is not a decimal number")
        if (exact && mantissa < (1L shl 53) && exp10 in -22..22) {
            val m = mantissa.toDouble()
            val v = if (exp10 >= 0) m * POW10[exp10] else m / POW10[-exp10]
            return if (negative) -v else v
        }
        if (mantissa == 0L && exact) return if (negative) -0.0 else 0.0
        return String(buf, first, e - first, Charsets.US_ASCII).replace(',', '.').toDouble()
    }

    private fun special(s: Int, e: Int, i: Int): Double {
        if (e - s > 9) throw FieldError("'${excerpt(i)}' is not a number")
        // Any case, as the tools that write them spell them (Java NaN/Infinity, C and Python nan/inf, R and MATLAB Inf, NAN).
        return when (String(buf, s, e - s, Charsets.UTF_8).lowercase().removePrefix("+")) {
            "nan", "-nan" -> Double.NaN
            "infinity", "inf" -> Double.POSITIVE_INFINITY
            "-infinity", "-inf" -> Double.NEGATIVE_INFINITY
            else -> throw FieldError("'${excerpt(i)}' is not a number")
        }
    }

    /** The current line's fields as header names: trimmed, BOM and quotes removed. */
    fun names(): List<String> = (0 until count).map { text(it).trim().removeSurrounding("\"").trim() }

    /**
     * Reads the header, the first line, of every table (plain IMU and orientation tables,
     * session streams, exports). An empty input is an error saying what header was [expected]
     * (null: just "empty file"). The caller closes the reader when this or its checks throw.
     */
    fun header(expected: String?): CsvHeader {
        if (!nextLine()) throw DataFormatException(sourceName, 1, 0, if (expected == null) "empty file" else "empty file: expected a header $expected")
        headerFields = count
        return CsvHeader(this, names(), expected)
    }

    override fun close(): Unit = input.close()

    companion object {
        /** How far past a CSV error in compressed data the reader looks for the damage that caused it, bytes. */
        const val DAMAGE_CHECK_BYTES: Long = 256L shl 20
        const val MAX_LINE_BYTES = 1 shl 20

        /** Times beyond this (s) do not fit a nanosecond Long. */
        const val MAX_TIME_S = 9.2e9

        /** [nextRow]: a row of plain numbers was parsed. */
        const val ROW = 0

        /** [nextRow]: a line to read through the general accessors. */
        const val LINE = 1

        /** [nextRow]: the end of the input. */
        const val END = 2
        private const val MORE = 3
        private const val EXACT_MANTISSA = 1L shl 53
        private const val NL_INT = '\n'.code
        private const val CR_INT = '\r'.code
        private const val MINUS_INT = '-'.code
        private const val PLUS_INT = '+'.code
        private const val DOT_INT = '.'.code
        private const val COMMA_INT = ','.code
        private const val ZERO_INT = '0'.code
        private const val NINE_INT = '9'.code
        private const val NL = '\n'.code.toByte()
        private const val CR = '\r'.code.toByte()
        private const val MINUS = '-'.code.toByte()
        private const val PLUS = '+'.code.toByte()
        private const val DOT = '.'.code.toByte()
        private const val COMMA = ','.code.toByte()
        private const val QUOTE = '"'.code.toByte()
        private const val SPACE = ' '.code.toByte()
        const val EXCERPT_CHARS = 24

        /**
         * The header names in [line] (a first line sniffed as text), split by this tokenizer at
         * [separator] as [names] does (a quote left open runs to the end); empty when it cannot be read.
         */
        fun headerNames(line: String, separator: Char = ','): List<String> = try {
            ByteCsvReader(line.toByteArray(Charsets.UTF_8).inputStream(), "header", separator.code.toByte()).use {
                if (it.nextLine()) it.names() else emptyList()
            }
        } catch (e: DataFormatException) {
            emptyList()
        }

        /** [text] cut to [EXCERPT_CHARS] characters with control characters, quotes and backslashes escaped. */
        fun escapedExcerpt(text: String): String {
            val cut = text.length > EXCERPT_CHARS
            val sb = StringBuilder()
            for (c in text.take(EXCERPT_CHARS)) {
                when {
                    c == '\\' || c == '\'' || c == '"' -> sb.append('\\').append(c)
                    c < ' ' || c == '\u007f' || c == '\ufeff' || c.isSurrogate() -> sb.append("\\u%04x".format(c.code))
                    else -> sb.append(c)
                }
            }
            if (cut) sb.append("…")
            return sb.toString()
        }
        private const val ZERO = '0'.code.toByte()
        private val POW10 = DoubleArray(23) { k -> "1e$k".toDouble() }
        private val LONG_POW10 = LongArray(9).also { p -> p[0] = 1L; for (i in 1 until 9) p[i] = p[i - 1] * 10L }
        private const val ASCII_ZEROS = 0x30303030_30303030L

        private fun littleEndian(b: ByteArray): java.nio.ByteBuffer = java.nio.ByteBuffer.wrap(b).order(java.nio.ByteOrder.LITTLE_ENDIAN)

        /**
         * How many of the 8 bytes of x (bytes − '0', the first in the lowest byte) are digits
         * before the first that is not: a byte is a digit when neither x nor x + 0x76 sets its
         * high bit (borrows and carries only reach the bytes after the first non-digit).
         */
        private fun digitRun(x: Long): Int =
            java.lang.Long.numberOfTrailingZeros((x or (x + 0x76767676_76767676L)) and HIGH_BITS) ushr 3

        private const val HIGH_BITS = -0x7f7f7f7f_7f7f7f80L // 0x8080808080808080

        /** The value of the first [n] (1..8) digits of x (as [digitRun]): in pairs, then fours, then all eight. */
        private fun digitsValue(x: Long, n: Int): Long {
            var v = x shl (8 * (8 - n)) // the n digits last, zeros before them
            v = v * 10L + (v ushr 8)
            v = (((v and 0x000000FF_000000FFL) * 0x000F4240_00000064L) + (((v ushr 16) and 0x000000FF_000000FFL) * 0x00002710_00000001L)) ushr 32
            return v
        }
    }
}

/** A table's header line: its [names] and their positions, and errors that name the expected header. */
internal class CsvHeader(private val csv: ByteCsvReader, val names: List<String>, private val expected: String?) {
    /** Fields per row: the header's count. */
    val fieldCount: Int get() = names.size

    /** The field of column [name], or an error at the header naming the columns expected. */
    fun require(name: String): Int {
        val i = names.indexOf(name)
        if (i < 0) throw DataFormatException(csv.sourceName, 1, 1, "header lacks column '$name'" + (expected?.let { "; expected $it" } ?: ""))
        return i
    }
}

/** A field that is not what its column needs; the caller adds the file, line and column. */
internal class FieldError(val reason: String) : RuntimeException(reason, null, false, false)
