package dev.motionfusion.core.io

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.ByteArrayInputStream
import java.util.Random

class ByteCsvReaderTest {
    private fun reader(text: String) = ByteCsvReader(ByteArrayInputStream(text.toByteArray()), "t.csv")

    @Test
    fun `numbers parse exactly like Double parseDouble`() {
        val r = Random(5)
        val samples = ArrayList<String>()
        repeat(100_000) {
            samples += when (it % 5) {
                0 -> r.nextGaussian().toString()
                1 -> (r.nextGaussian() * 1e-5).toFloat().toString()
                2 -> java.lang.Double.toString(Double.fromBits(r.nextLong()))
                3 -> "${r.nextInt()}.${r.nextInt(1_000_000_000)}e${r.nextInt(40) - 20}"
                else -> "-0.${"0".repeat(r.nextInt(5))}${r.nextLong().let { x -> if (x < 0) -x else x }}"
            }
        }
        val csv = reader(samples.filter { !it.contains("Infinity") && !it.contains("NaN") }.joinToString("\n") + "\n")
        var n = 0
        while (csv.nextLine()) {
            val t = csv.text(0)
            assertEquals(t.toDouble().toRawBits(), csv.parseDouble(0).toRawBits(), t)
            n++
        }
        assertTrue(n > 99_000)
    }

    @Test
    fun `fields lines and columns`() {
        val csv = reader("a,b,c\r\n\n1,,x\n  \nlast,2")
        assertTrue(csv.nextLine())
        assertEquals(3, csv.count)
        assertTrue(csv.nextLine())
        assertEquals(3L, csv.lineNumber)
        assertTrue(csv.isEmpty(1))
        assertTrue(csv.parseDouble(1, emptyIsNaN = true).isNaN())
        assertThrows(FieldError::class.java) { csv.parseDouble(2) }
        assertEquals(4, csv.column(2))
        assertTrue(csv.nextLine()) // a line of spaces is not empty
        assertTrue(csv.nextLine())
        assertFalse(csv.endedWithNewline)
        assertEquals(2L, csv.parseLong(1))
        assertFalse(csv.nextLine())
    }

    @Test
    fun `malformed numbers are errors, specials are read`() {
        for (bad in listOf("1,5", "0x10", "1.0f", "--1", "1e", ".", "-", "1.2.3", "12a", "e5", "1e+")) {
            val csv = reader(bad.replace(",", ";") + "\n")
            csv.nextLine()
            assertThrows(FieldError::class.java, { csv.parseDouble(0) }, bad)
        }
        val csv = reader("NaN,Infinity,-Infinity,+1.5,1E3,007\n")
        csv.nextLine()
        assertTrue(csv.parseDouble(0).isNaN())
        assertEquals(Double.POSITIVE_INFINITY, csv.parseDouble(1))
        assertEquals(Double.NEGATIVE_INFINITY, csv.parseDouble(2))
        assertEquals(1.5, csv.parseDouble(3))
        assertEquals(1000.0, csv.parseDouble(4))
        assertEquals(7L, csv.parseLong(5))
    }

    @Test
    fun `a line without end longer than the limit is an error, not a memory blow-up`() {
        val big = ByteArray(ByteCsvReader.MAX_LINE_BYTES + 10) { 'a'.code.toByte() }
        val csv = ByteCsvReader(ByteArrayInputStream(big), "big.csv")
        val e = assertThrows(DataFormatException::class.java) { csv.nextLine() }
        assertTrue(e.message!!.startsWith("big.csv:1:"), e.message)
    }

    @Test
    fun `long lines across buffer boundaries`() {
        val line = (0 until 20_000).joinToString(",") { (it * 0.5).toString() }
        val csv = reader("$line\n$line\n")
        repeat(2) {
            assertTrue(csv.nextLine())
            assertEquals(20_000, csv.count)
            assertEquals(9999.5, csv.parseDouble(19_999))
        }
        assertFalse(csv.nextLine())
    }

    @Test
    fun `quoted fields, a byte order mark and the dialects of phyphox`() {
        val csv = ByteCsvReader(ByteArrayInputStream("\uFEFF\"Time (s)\";\"a;b\";c\n1,5;2.5;-3,25E-1\n".toByteArray()), "p.csv", ';'.code.toByte(), decimalComma = true)
        assertTrue(csv.nextLine())
        assertEquals(listOf("Time (s)", "a;b", "c"), csv.names())
        assertTrue(csv.nextLine())
        assertEquals(1.5, csv.parseDouble(0))
        assertEquals(2.5, csv.parseDouble(1))
        assertEquals(-0.325, csv.parseDouble(2))
    }

    @Test
    fun `a float in an integer column is an error`() {
        val csv = reader("1.7e18,1700000000000000000.0\n")
        csv.nextLine()
        assertThrows(FieldError::class.java) { csv.parseLong(0) }
        assertThrows(FieldError::class.java) { csv.parseLong(1) }
    }

    @Test
    fun `the line bound can be set lower`() {
        val csv = ByteCsvReader(ByteArrayInputStream(ByteArray(200_000) { 'a'.code.toByte() }), "big.csv", maxLineBytes = 1 shl 16)
        val e = assertThrows(DataFormatException::class.java) { csv.nextLine() }
        assertTrue(e.reason.contains("longer than 65536"), e.reason)
    }
}
