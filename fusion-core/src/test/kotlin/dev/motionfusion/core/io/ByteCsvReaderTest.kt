package dev.motionfusion.core.io

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.ByteArrayInputStream
import java.util.Random

class ByteCsvReaderTest {
    @Test
    fun `a sniffed header line is split by the same tokenizer as the rows`() {
        assertEquals(listOf("time", "a,b", "x"), ByteCsvReader.headerNames("\"time\",\"a,b\",x"))
        assertEquals(listOf("Time (s)", "X (rad/s)"), ByteCsvReader.headerNames("\"Time (s)\"\t\"X (rad/s)\"", '\t'))
        assertEquals(listOf("t;s", "gx"), ByteCsvReader.headerNames("\"t;s\";gx", ';'))
        assertEquals(listOf("open quote,t_s"), ByteCsvReader.headerNames("\"open quote,t_s")) // quoted to the end of the line
    }

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
    fun `not-a-number and infinity in the spellings other tools write`() {
        // Java, C/Python, R/MATLAB, Excel-style upper case.
        val nans = listOf("NaN", "nan", "NAN", "-NaN", "+nan")
        val infs = listOf("Infinity", "inf", "Inf", "INF", "+Infinity", "infinity")
        val negative = listOf("-Infinity", "-inf", "-Inf", "-INF", "-infinity")
        val csv = reader((nans + infs + negative).joinToString(",") + "\n")
        csv.nextLine()
        var k = 0
        for (s in nans) assertTrue(csv.parseDouble(k++).isNaN(), s)
        for (s in infs) assertEquals(Double.POSITIVE_INFINITY, csv.parseDouble(k++), s)
        for (s in negative) assertEquals(Double.NEGATIVE_INFINITY, csv.parseDouble(k++), s)
        for (bad in listOf("nanx", "infinit", "in", "Infinityy")) {
            val b = reader("$bad\n")
            b.nextLine()
            assertThrows(FieldError::class.java, { b.parseDouble(0) }, bad)
        }
    }

    @Test
    fun `a last line cut short is named as such, a short line inside the file is not`() {
        val cut = reader("t,a,b\n1,2,3\n4,5")
        cut.header(null)
        assertTrue(cut.nextRecord())
        val e = assertThrows(DataFormatException::class.java) { cut.nextRecord() }
        assertTrue("t.csv:3:" in e.message!! && "the last line, without an end of line" in e.message!!, e.message)
        val inside = reader("t,a,b\n4,5\n1,2,3\n")
        inside.header(null)
        val e2 = assertThrows(DataFormatException::class.java) { inside.nextRecord() }
        assertFalse("last line" in e2.message!!, e2.message)
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

    /** Hands out at most a few bytes per read, so lines cross the reader's buffer ends everywhere. */
    private class Trickle(private val bytes: ByteArray, seed: Long) : java.io.InputStream() {
        private val r = Random(seed)
        private var at = 0
        override fun read(): Int = if (at < bytes.size) bytes[at++].toInt() and 0xff else -1
        override fun read(b: ByteArray, off: Int, len: Int): Int {
            if (at == bytes.size) return -1
            val n = minOf(len, bytes.size - at, 1 + r.nextInt(if (r.nextInt(4) == 0) 70_000 else 40))
            System.arraycopy(bytes, at, b, off, n)
            at += n
            return n
        }
    }

    /** A field as a table might hold it: mostly plain decimals, and every shape the one-pass parse must leave to the general path. */
    private fun field(r: Random): String = when (r.nextInt(20)) {
        in 0..7 -> r.nextGaussian().toFloat().toString().let { if (it.contains('E')) "0.5" else it }
        8 -> (r.nextGaussian() * 1e3).toString().let { if (it.contains('E')) "-1" else it }
        9 -> "${if (r.nextBoolean()) "-" else "+"}${r.nextInt(1000)}.${r.nextInt(1000)}"
        10 -> (r.nextLong() ushr r.nextInt(64)).toString() // up to 19 digits, beyond 2^53
        11 -> "0." + "0".repeat(r.nextInt(30)) + (1 + r.nextInt(999))
        12 -> listOf("1e5", "-2.5E-3", "NaN", "-Infinity", "", " 1.5", "1.5 ", "\"2.5\"", ".5", "5.", "-", ".", "1.2.3", "12a", "-0", "-0.000")[r.nextInt(16)]
        13 -> r.nextInt(100_000).toString()
        14 -> "${r.nextInt(100)}.${"9".repeat(r.nextInt(24))}"
        else -> String.format(java.util.Locale.ROOT, "%.9f", r.nextGaussian() * 10)
    }

    @Test
    fun `one-pass rows give the doubles of Double parseDouble and the general path, and leave every other line to it`() {
        val r = Random(11)
        val lines = ArrayList<String>()
        lines += "a,b,c,d,e"
        repeat(60_000) {
            val n = if (r.nextInt(50) == 0) 4 + r.nextInt(3) else 5 // some rows with a wrong field count
            val line = (0 until n).joinToString(",") { field(r) }
            lines += when (r.nextInt(100)) {
                0 -> "" // empty line
                1 -> "$line\r" // CRLF
                else -> line
            }
        }
        val text = lines.joinToString("\n") + (if (r.nextBoolean()) "\n" else "")
        val bytes = text.toByteArray()
        // Column b is ignored (slot -1), the others go to out[3 - i] (any order).
        val slot = intArrayOf(3, -1, 2, 1, 0)
        val fast = ByteCsvReader(Trickle(bytes, 3), "t.csv")
        val general = ByteCsvReader(ByteArrayInputStream(bytes), "t.csv")
        val out = DoubleArray(4)
        var rows = 0
        var others = 0
        var lastLine = 0L
        while (true) {
            val kind = fast.nextRow(5, slot, out)
            val more = general.nextLine()
            if (kind == ByteCsvReader.END) {
                assertFalse(more)
                break
            }
            assertTrue(more)
            assertEquals(general.lineNumber, fast.lineNumber)
            assertEquals(general.lineText(), fast.lineText())
            assertEquals(general.count, fast.count)
            assertEquals(general.endedWithNewline, fast.endedWithNewline)
            for (i in 0 until general.count) assertEquals(general.column(i), fast.column(i))
            val previousLine = lastLine
            lastLine = general.lineNumber
            if (kind == ByteCsvReader.ROW) {
                rows++
                for (i in 0 until 5) {
                    if (slot[i] < 0) continue
                    val t = general.text(i)
                    assertEquals(t.toDouble().toRawBits(), out[slot[i]].toRawBits(), t)
                    assertEquals(general.parseDouble(i).toRawBits(), out[slot[i]].toRawBits(), t)
                }
            } else {
                assertEquals(ByteCsvReader.LINE, kind)
                others++
                // Left to the general path only where it is not a plain row of 5 fields.
                val raw = general.lineText().removeSuffix("\r").split(',') // the generated fields hold no comma
                val plain = raw.size == 5 && raw.indices.all { i ->
                    val f = raw[i]
                    if (slot[i] < 0) {
                        '"' !in f
                    } else {
                        Regex("[-+]?[0-9]*\\.?[0-9]*").matches(f) && f.count { it.isDigit() } in 1..18 &&
                            f.substringAfter('.', "").length <= 22 && f.filter { it.isDigit() }.toLong() < (1L shl 53)
                    }
                }
                // (A plain row right after an empty line comes through the general path, which skips the empty one; so does a last line without newline.)
                assertFalse(plain && general.lineNumber > 1 && general.lineNumber == previousLine + 1 && general.endedWithNewline, "line ${general.lineNumber} '${general.lineText()}' is plain")
            }
        }
        assertTrue(rows > 20_000, "rows parsed in one pass: $rows")
        assertTrue(others > 20_000, "lines left to the general path: $others")
    }

    @Test
    fun `one-pass rows with a decimal comma and another separator`() {
        val csv = ByteCsvReader(ByteArrayInputStream("t;x\n1,5;-2,25\n3;4.5\n".toByteArray()), "p.csv", ';'.code.toByte(), decimalComma = true)
        val out = DoubleArray(2)
        assertEquals(ByteCsvReader.LINE, csv.nextRow(2, intArrayOf(0, 1), out)) // the header
        assertEquals(ByteCsvReader.ROW, csv.nextRow(2, intArrayOf(0, 1), out))
        assertEquals(1.5, out[0])
        assertEquals(-2.25, out[1])
        assertEquals(ByteCsvReader.ROW, csv.nextRow(2, intArrayOf(0, 1), out))
        assertEquals(4.5, out[1])
        assertEquals(ByteCsvReader.END, csv.nextRow(2, intArrayOf(0, 1), out))
    }
}
