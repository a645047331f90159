package dev.motionfusion.core.io

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.math.BigDecimal
import java.util.Random

class AsciiNumbersTest {
    private fun significantDigits(s: String): Int =
        BigDecimal(s).stripTrailingZeros().precision()

    @Test
    fun `random floats of every magnitude read back exactly and are never longer than Float toString`() {
        val r = Random(42)
        repeat(300_000) {
            val f = when (it % 3) {
                0 -> Float.fromBits(r.nextInt()) // any bit pattern
                1 -> (r.nextGaussian() * 10.0).toFloat() // sensor-like
                else -> (r.nextDouble() * Math.pow(10.0, r.nextInt(30) - 15.0)).toFloat()
            }
            if (f.isNaN()) return@repeat
            val s = AsciiNumbers.floatToString(f)
            val back = s.toFloat()
            assertEquals(f.toRawBits(), back.toRawBits(), "$f written as $s read back as $back")
            if (f.isFinite() && f != 0f) {
                assertTrue(significantDigits(s) <= 9, s)
            }
        }
    }

    @Test
    fun `shortest forms of familiar values`() {
        val cases = mapOf(
            0f to "0", -0f to "-0", 1f to "1", -1f to "-1", 9.80665f to "9.80665", 0.1f to "0.1",
            123456.7f to "123456.7", 1e-7f to "0.0000001", 1.5e-12f to "1.5E-12", 100f to "100",
            3.4028235e38f to "3.4028235E38", Float.NaN to "NaN", Float.NEGATIVE_INFINITY to "-Infinity",
            48.123f to "48.123", 1e8f to "100000000", 1e9f to "1E9", 0.001f to "0.001",
        )
        for ((f, s) in cases) assertEquals(s, AsciiNumbers.floatToString(f), "for $f")
    }

    @Test
    fun `digits are minimal for short decimals`() {
        val r = Random(7)
        repeat(50_000) {
            val digits = 1 + r.nextInt(6)
            val m = (r.nextInt(Math.pow(10.0, digits.toDouble()).toInt() - 1) + 1)
            val s = "${m}E${r.nextInt(16) - 8}"
            val f = s.toFloat()
            val out = AsciiNumbers.floatToString(f)
            assertTrue(significantDigits(out) <= significantDigits(s), "$s → $out")
        }
    }

    @Test
    fun `fixed decimals`() {
        assertEquals("-12.345", AsciiNumbers.fixedToString(-12.345, 6))
        assertEquals("0", AsciiNumbers.fixedToString(-0.0000001, 6))
        assertEquals("1", AsciiNumbers.fixedToString(0.9999999999, 6))
        assertEquals("0.000001", AsciiNumbers.fixedToString(0.000001, 6))
        assertEquals("180", AsciiNumbers.fixedToString(180.0, 4))
        assertEquals("NaN", AsciiNumbers.fixedToString(Double.NaN, 4))
        val r = Random(3)
        repeat(100_000) {
            val v = (r.nextDouble() - 0.5) * Math.pow(10.0, r.nextInt(12) - 3.0)
            val d = r.nextInt(10)
            val s = AsciiNumbers.fixedToString(v, d)
            assertEquals(BigDecimal(v).setScale(d, java.math.RoundingMode.HALF_UP).toDouble(), s.toDouble(), 1.5 * Math.pow(10.0, -d.toDouble()) + 2 * Math.ulp(v), "$v/$d → $s")
        }
    }

    @Test
    fun `fixed decimals equal BigDecimal's digits of the documented rounding, and the exact rounding away from midpoints`() {
        val r = Random(5)
        val b = ByteArray(48)
        var exact = 0
        repeat(1_000_000) {
            val v = when (it % 4) {
                0 -> r.nextDouble() * 2 - 1 // quaternion components
                1 -> (r.nextDouble() - 0.5) * 360 // angles
                2 -> r.nextDouble() * 3600 // times
                else -> (r.nextDouble() - 0.5) * Math.pow(10.0, r.nextInt(13) - 3.0)
            }
            val d = if (it % 2 == 0) intArrayOf(9, 4, 5)[it % 3] else r.nextInt(10)
            val s = String(b, 0, AsciiNumbers.fixed(b, 0, v, d), Charsets.US_ASCII)
            val m = Math.round(Math.abs(v) * Math.pow(10.0, d.toDouble()))
            val expected = if (m == 0L) "0" else BigDecimal.valueOf(if (v < 0) -m else m, d).stripTrailingZeros().toPlainString()
            assertEquals(expected, s, "$v to $d decimals")
            // Away from a rounding midpoint (where the product's own rounding decides) it is the exact rounding of v.
            val scaled = BigDecimal(v).movePointRight(d)
            val frac = scaled.subtract(BigDecimal(scaled.toBigInteger())).abs().toDouble()
            if (Math.abs(frac - 0.5) > 1e-6 && Math.abs(v) * Math.pow(10.0, d.toDouble()) < 1e9) {
                exact++
                val correct = BigDecimal(v).setScale(d, java.math.RoundingMode.HALF_UP)
                assertEquals(0, correct.compareTo(BigDecimal(s)), "$v to $d decimals: $s, exactly $correct")
            }
        }
        assertTrue(exact > 600_000, "compared $exact")
    }

    @Test
    fun `longs`() {
        val b = ByteArray(32)
        for (v in listOf(0L, 1L, -1L, 9L, 10L, 123456789012345L, Long.MAX_VALUE, Long.MIN_VALUE, -1000L)) {
            assertEquals(v.toString(), String(b, 0, AsciiNumbers.long(b, 0, v), Charsets.US_ASCII))
        }
    }
}
