/*
 * Locale-independent number formatting into a byte array, without String.format and without
 * allocating: the hot path of the session writer and of `fusion replay`.
 *
 * Floats are written with the fewest significant digits (at most 9) that read back, with
 * Float.parseFloat or any correctly rounding parser (pandas, spreadsheets), as the same float.
 * Doubles with a fixed number of decimals are written by [fixed]. Longs and ints exactly.
 * The decimal separator is always '.', the exponent marker 'E', no grouping.
 */
package dev.motionfusion.core.io

import kotlin.math.abs

public object AsciiNumbers {
    /** Longest output of [float]: sign, 9 digits, point, up to 7 leading zeros, exponent. */
    internal const val MAX_FLOAT_CHARS: Int = 24

    /** Longest output of [long]. */
    internal const val MAX_LONG_CHARS: Int = 20

    private val POW10 = DoubleArray(23) { i -> "1e$i".toDouble() }
    private val LONG_POW10 = LongArray(19).also { p -> p[0] = 1L; for (i in 1 until 19) p[i] = p[i - 1] * 10L }
    private val NAN = "NaN".toByteArray(Charsets.US_ASCII)
    private val INF = "Infinity".toByteArray(Charsets.US_ASCII)

    /** Writes [v] at buf[pos]; returns the position after it. */
    public fun long(buf: ByteArray, pos: Int, v: Long): Int {
        var p = pos
        if (v == Long.MIN_VALUE) {
            for (c in "-9223372036854775808") buf[p++] = c.code.toByte()
            return p
        }
        var x = v
        if (x < 0) {
            buf[p++] = '-'.code.toByte()
            x = -x
        }
        val digits = digitCount(x)
        var end = p + digits
        val result = end
        do {
            buf[--end] = ('0'.code + (x % 10L).toInt()).toByte()
            x /= 10L
        } while (x != 0L)
        return result
    }

    private fun digitCount(x: Long): Int {
        var d = 1
        while (d < 19 && x >= LONG_POW10[d]) d++
        return d
    }

    /**
     * Writes the shortest decimal (≤ 9 significant digits) that parses back to exactly [f]; plain
     * notation for magnitudes in [1e-7, 1e9), scientific ("1.5E-12") outside. Returns the new position.
     */
    public fun float(buf: ByteArray, pos: Int, f: Float): Int {
        var p = pos
        if (f.isNaN()) return copy(NAN, buf, p)
        if (f.isInfinite()) {
            if (f < 0f) buf[p++] = '-'.code.toByte()
            return copy(INF, buf, p)
        }
        if (f == 0f) {
            if (1f / f < 0f) buf[p++] = '-'.code.toByte()
            buf[p++] = '0'.code.toByte()
            return p
        }
        if (f < 0f) buf[p++] = '-'.code.toByte()
        val v = abs(f.toDouble())
        if (v < 1e-13 || v >= 1e13) return copyString(abs(f).toString(), buf, p) // outside the exact fast path
        // e10 = floor(log10(v)), corrected for rounding of log10 near powers of ten.
        var e10 = kotlin.math.floor(kotlin.math.log10(v)).toInt()
        if (scaled(v, -e10) >= 10.0) e10++ else if (scaled(v, -e10) < 1.0) e10--
        val target = abs(f)
        for (digits in 6..9) {
            val shift = digits - 1 - e10 // v · 10^shift has `digits` digits before the point
            var m = Math.round(scaled(v, shift))
            var e = e10
            if (m >= LONG_POW10[digits]) { // rounding carried into a new digit: 9.9999999 → 10.00000
                m /= 10L
                e++
            }
            if (digits == 9 || roundTrips(m, e - (digits - 1), target)) {
                return writeDecimal(buf, p, m, digits, e)
            }
        }
        error("unreachable")
    }

    /** v · 10^k computed with one correctly rounded operation on exact operands (|k| ≤ 22). */
    private fun scaled(v: Double, k: Int): Double = if (k >= 0) v * POW10[k] else v / POW10[-k]

    /**
     * True when the decimal m · 10^exp reads back as [target] under correct rounding. The double
     * m · 10^exp is correctly rounded; unless it sits exactly on a midpoint between two floats,
     * its float rounding equals the correct float rounding of the exact decimal.
     */
    private fun roundTrips(m: Long, exp: Int, target: Float): Boolean {
        if (exp < -22 || exp > 22) return false
        val d = if (exp >= 0) m.toDouble() * POW10[exp] else m.toDouble() / POW10[-exp]
        val f = d.toFloat()
        if (f != target) return false
        val fd = f.toDouble()
        if (d == fd) return true
        val mid = if (d > fd) 0.5 * (fd + Math.nextUp(f).toDouble()) else 0.5 * (fd + Math.nextDown(f).toDouble())
        // On a midpoint the double may or may not be the exact decimal: ask the exact parser (rare).
        return d != mid || java.lang.Float.parseFloat("${m}E$exp") == target
    }

    /** Writes the integer m of `digits` digits as d.ddd × 10^e, trailing zeros removed. */
    private fun writeDecimal(buf: ByteArray, pos: Int, mantissa: Long, digits: Int, e: Int): Int {
        var m = mantissa
        var n = digits
        while (n > 1 && m % 10L == 0L) {
            m /= 10L
            n--
        }
        var p = pos
        if (e in -7..8) {
            if (e < 0) {
                buf[p++] = '0'.code.toByte()
                buf[p++] = '.'.code.toByte()
                for (i in 0 until -e - 1) buf[p++] = '0'.code.toByte()
                return writeDigits(buf, p, m, n)
            }
            val intDigits = e + 1
            if (n <= intDigits) {
                p = writeDigits(buf, p, m, n)
                for (i in 0 until intDigits - n) buf[p++] = '0'.code.toByte()
                return p
            }
            val intPart = m / LONG_POW10[n - intDigits]
            val frac = m % LONG_POW10[n - intDigits]
            p = writeDigits(buf, p, intPart, intDigits)
            buf[p++] = '.'.code.toByte()
            return writeDigits(buf, p, frac, n - intDigits)
        }
        p = writeDigits(buf, p, m / LONG_POW10[n - 1], 1)
        if (n > 1) {
            buf[p++] = '.'.code.toByte()
            p = writeDigits(buf, p, m % LONG_POW10[n - 1], n - 1)
        }
        buf[p++] = 'E'.code.toByte()
        return long(buf, p, e.toLong())
    }

    /** Writes [v] as exactly [count] digits (leading zeros kept). */
    private fun writeDigits(buf: ByteArray, pos: Int, v: Long, count: Int): Int {
        var x = v
        var i = pos + count
        while (i > pos) {
            buf[--i] = ('0'.code + (x % 10L).toInt()).toByte()
            x /= 10L
        }
        return pos + count
    }

    /**
     * Writes [v] rounded to [decimals] places (0..9), e.g. "-12.345000" for decimals 6; trailing
     * zeros are removed ("-12.345"). The rounding is that of Math.round(|v| · 10^decimals) (half
     * up, after the product's own rounding); a result of 0 is written "0", without sign. Values
     * beyond ±9e9 and non-finite ones use Double.toString. Nothing is allocated on the way.
     */
    public fun fixed(buf: ByteArray, pos: Int, v: Double, decimals: Int): Int {
        var p = pos
        val a = abs(v)
        if (!(a < 9e9)) return copyString(if (v.isNaN()) "NaN" else v.toString(), buf, p)
        val m = Math.round(a * LONG_POW10[decimals])
        if (m == 0L) {
            buf[p] = '0'.code.toByte()
            return p + 1
        }
        if (v < 0) buf[p++] = '-'.code.toByte()
        // Integer and fraction parts; the divisions by constants compile to multiplications.
        val ip: Long
        var fp: Int
        when (decimals) {
            9 -> { ip = m / 1_000_000_000L; fp = (m - ip * 1_000_000_000L).toInt() }
            5 -> { ip = m / 100_000L; fp = (m - ip * 100_000L).toInt() }
            4 -> { ip = m / 10_000L; fp = (m - ip * 10_000L).toInt() }
            0 -> { ip = m; fp = 0 }
            else -> { ip = m / LONG_POW10[decimals]; fp = (m - ip * LONG_POW10[decimals]).toInt() }
        }
        p = if (ip < 10_000L) small(buf, p, ip.toInt()) else long(buf, p, ip)
        if (fp == 0) return p
        var n = decimals
        while (fp % 10 == 0) {
            fp /= 10
            n--
        }
        buf[p++] = '.'.code.toByte()
        val end = p + n
        var i = end
        while (n >= 2) {
            val q = fp / 100
            val r = fp - q * 100
            buf[--i] = DIGIT_ONES[r]
            buf[--i] = DIGIT_TENS[r]
            fp = q
            n -= 2
        }
        if (n == 1) buf[--i] = ('0'.code + fp).toByte()
        return end
    }

    /** Writes 0 ≤ [v] < 10,000 without leading zeros; returns the position after it. */
    private fun small(buf: ByteArray, p: Int, v: Int): Int {
        if (v < 10) {
            buf[p] = ('0'.code + v).toByte()
            return p + 1
        }
        if (v < 100) {
            buf[p] = DIGIT_TENS[v]
            buf[p + 1] = DIGIT_ONES[v]
            return p + 2
        }
        val h = v / 100
        val r = v - h * 100
        if (h < 10) {
            buf[p] = ('0'.code + h).toByte()
            buf[p + 1] = DIGIT_TENS[r]
            buf[p + 2] = DIGIT_ONES[r]
            return p + 3
        }
        buf[p] = DIGIT_TENS[h]
        buf[p + 1] = DIGIT_ONES[h]
        buf[p + 2] = DIGIT_TENS[r]
        buf[p + 3] = DIGIT_ONES[r]
        return p + 4
    }

    private val DIGIT_TENS = ByteArray(100) { ('0'.code + it / 10).toByte() }
    private val DIGIT_ONES = ByteArray(100) { ('0'.code + it % 10).toByte() }

    private fun copy(src: ByteArray, buf: ByteArray, pos: Int): Int {
        src.copyInto(buf, pos)
        return pos + src.size
    }

    private fun copyString(s: String, buf: ByteArray, pos: Int): Int {
        var p = pos
        for (c in s) buf[p++] = c.code.toByte()
        return p
    }

    /** The output of [float] as a String (tests, headers). */
    internal fun floatToString(f: Float): String {
        val b = ByteArray(MAX_FLOAT_CHARS + 8)
        return String(b, 0, float(b, 0, f), Charsets.US_ASCII)
    }

    /** The output of [fixed] as a String. */
    internal fun fixedToString(v: Double, decimals: Int): String {
        val b = ByteArray(48)
        return String(b, 0, fixed(b, 0, v, decimals), Charsets.US_ASCII)
    }
}
