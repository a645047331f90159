/*
 * A fast, streaming reader of comma-separated ASCII numbers straight from bytes: no String per
 * line, no Double.parseDouble on the common path. Used for the session streams, where replay
 * must read millions of rows per second. Memory is one buffer (64 KiB, grown for long lines up
 * to [MAX_LINE_BYTES]).
 */
package dev.motionfusion.core.io

import java.io.Closeable
import java.io.InputStream

internal class ByteCsvReader(
    private val input: InputStream,
    val sourceName: String,
    private val separator: Byte = ','.code.toByte(),
) : Closeable {
    private var buf = ByteArray(1 shl 16)
    private var pos = 0
    private var limit = 0
    private var eof = false

    private var lineStart = 0
    private var lineEnd = 0
    private var starts = IntArray(16)
    private var ends = IntArray(16)

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
                return true
            }
            val scanned = scan - pos
            fill()
            scan = pos + scanned
        }
    }

    /** Moves unread bytes to the front (growing the buffer for a long line) and reads more. */
    private fun fill() {
        val unread = limit - pos
        if (pos > 0) {
            System.arraycopy(buf, pos, buf, 0, unread)
        } else if (unread == buf.size) {
            if (buf.size >= MAX_LINE_BYTES) {
                throw DataFormatException(sourceName, lineNumber + 1, 0, "line longer than $MAX_LINE_BYTES bytes: not a CSV text file?")
            }
            buf = buf.copyOf(buf.size * 2)
        }
        pos = 0
        limit = unread
        val n = try {
            input.read(buf, limit, buf.size - limit)
        } catch (e: java.util.zip.ZipException) {
            throw DataFormatException(sourceName, lineNumber + 1, 0, "corrupt compressed data: ${e.message}", e)
        } catch (e: java.io.EOFException) {
            throw DataFormatException(sourceName, lineNumber + 1, 0, "compressed data ends early: ${e.message}", e)
        }
        if (n < 0) eof = true else limit += n
    }

    private fun split() {
        count = 0
        var i = lineStart
        var start = i
        while (true) {
            if (i == lineEnd || buf[i] == separator) {
                if (count == starts.size) {
                    starts = starts.copyOf(count * 2)
                    ends = ends.copyOf(count * 2)
                }
                starts[count] = start
                ends[count] = i
                count++
                if (i == lineEnd) return
                start = i + 1
            }
            i++
        }
    }

    /** The current line as text (headers, messages). */
    fun lineText(): String = String(buf, lineStart, lineEnd - lineStart, Charsets.UTF_8)

    /** Field [i] as text. */
    fun text(i: Int): String = String(buf, starts[i], ends[i] - starts[i], Charsets.UTF_8)

    /** 1-based character column of field [i] (counting UTF-8 characters, not bytes). */
    fun column(i: Int): Int = String(buf, lineStart, starts[i] - lineStart, Charsets.UTF_8).length + 1

    /** 1-based character column just after the end of the line. */
    fun endColumn(): Int = String(buf, lineStart, lineEnd - lineStart, Charsets.UTF_8).length + 1

    fun isEmpty(i: Int): Boolean = starts[i] == ends[i]

    /** A [DataFormatException] at field [i] of the current line. */
    fun error(i: Int, reason: String): DataFormatException =
        DataFormatException(sourceName, lineNumber, if (i < count) column(i) else endColumn(), reason)

    /** Field [i] as a decimal integer (optional sign, digits only). */
    fun parseLong(i: Int): Long {
        var p = starts[i]
        val e = ends[i]
        if (p == e) throw FieldError("empty field, expected an integer")
        var negative = false
        if (buf[p] == MINUS || buf[p] == PLUS) {
            negative = buf[p] == MINUS
            p++
            if (p == e) throw FieldError("'${text(i)}' is not an integer")
        }
        var v = 0L
        while (p < e) {
            val d = buf[p] - ZERO
            if (d !in 0..9) throw FieldError("'${text(i)}' is not an integer")
            if (v > (Long.MAX_VALUE - d) / 10L) throw FieldError("'${text(i)}' is out of range")
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
        val e = ends[i]
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
        if (p < e && buf[p] == DOT) {
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
            if (p == e) throw FieldError("'${text(i)}' is not a number")
            var x = 0
            while (p < e && buf[p] - ZERO in 0..9) {
                if (x < 100_000) x = x * 10 + (buf[p] - ZERO)
                p++
            }
            exp10 += if (expNegative) -x else x
        }
        if (p != e) throw FieldError("'${text(i)}' is not a decimal number")
        if (exact && mantissa < (1L shl 53) && exp10 in -22..22) {
            val m = mantissa.toDouble()
            val v = if (exp10 >= 0) m * POW10[exp10] else m / POW10[-exp10]
            return if (negative) -v else v
        }
        if (mantissa == 0L && exact) return if (negative) -0.0 else 0.0
        return String(buf, first, e - first, Charsets.US_ASCII).toDouble()
    }

    private fun special(s: Int, e: Int, i: Int): Double {
        val t = text(i)
        return when (t) {
            "NaN", "nan", "+NaN", "-NaN" -> Double.NaN
            "Infinity", "+Infinity", "inf", "+inf" -> Double.POSITIVE_INFINITY
            "-Infinity", "-inf" -> Double.NEGATIVE_INFINITY
            else -> throw FieldError(if (s == e) "empty field, expected a number" else "'$t' is not a number")
        }
    }

    override fun close(): Unit = input.close()

    companion object {
        const val MAX_LINE_BYTES = 1 shl 20
        private const val NL = '\n'.code.toByte()
        private const val CR = '\r'.code.toByte()
        private const val MINUS = '-'.code.toByte()
        private const val PLUS = '+'.code.toByte()
        private const val DOT = '.'.code.toByte()
        private const val ZERO = '0'.code.toByte()
        private val POW10 = DoubleArray(23) { k -> "1e$k".toDouble() }
    }
}
