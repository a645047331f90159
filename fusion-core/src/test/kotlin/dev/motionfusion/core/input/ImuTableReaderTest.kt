package dev.motionfusion.core.input

import dev.motionfusion.core.io.DataFormatException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.io.ByteArrayOutputStream
import java.util.zip.GZIPOutputStream

class ImuTableReaderTest {

    /** Rows as [t_s, gx … mz]. */
    private fun read(text: String): List<List<Double>> = read(text.toByteArray())

    private fun read(bytes: ByteArray): List<List<Double>> =
        ImuTableReader.open(bytes.inputStream(), "t.csv").use { r ->
            val rows = ArrayList<List<Double>>()
            while (r.next()) rows += listOf(r.timeS) + r.row.toList()
            rows
        }

    private fun error(text: String): DataFormatException =
        assertThrows { read(text) }

    @Test
    fun `reads every column in SI units`() {
        val rows = read("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n0.5,0.1,0.2,0.3,1,2,9.81,20,-5,-40\n0.51,1e-3,-2E-2,0,0,0,0,NaN,1,2\n")
        assertEquals(2, rows.size)
        assertEquals(listOf(0.5, 0.1, 0.2, 0.3, 1.0, 2.0, 9.81, 20.0, -5.0, -40.0), rows[0])
        assertEquals(-0.02, rows[1][2])
        assertTrue(rows[1][7].isNaN())
    }

    @Test
    fun `finds columns by name in any order and without magnetometer`() {
        ImuTableReader.open("az,ay,ax,gz,gy,gx,t_s,extra\r\n9,8,7,3,2,1,0.25,x\r\n".byteInputStream(), "t.csv").use { r ->
            assertFalse(r.hasMagnetometer)
            assertTrue(r.next())
            assertEquals(0.25, r.timeS)
            assertEquals(listOf(1.0, 2.0, 3.0, 7.0, 8.0, 9.0), r.row.take(6))
            assertTrue(r.row[6].isNaN())
            assertFalse(r.next())
        }
    }

    @Test
    fun `gzip is detected by content`() {
        val bos = ByteArrayOutputStream()
        GZIPOutputStream(bos).use { it.write("t_s,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,9.8\n".toByteArray()) }
        assertEquals(1.0, read(bos.toByteArray()).single()[0])
    }

    @Test
    fun `a bad number names file line and column`() {
        val e = error("t_s,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,9.8\n\n2,0,0,abc,0,0,9.8\n")
        assertEquals("t.csv", e.source)
        assertEquals(4, e.line)
        assertEquals(7, e.column)
        assertTrue(e.message!!.startsWith("t.csv:4:7: column gz"), e.message)
    }

    @Test
    fun `decimal comma, hexadecimal and type suffixes are rejected`() {
        for (bad in listOf("\"1,5\"", "0x1p3", "1.0f", "2d")) {
            val e = error("t_s,gx,gy,gz,ax,ay,az\n$bad,0,0,0,0,0,9.8\n")
            assertEquals(2, e.line, bad)
        }
    }

    @Test
    fun `a decimal comma in a comma file is a field count error at the first extra field`() {
        val e = error("t_s,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,9,81\n")
        assertEquals(2, e.line)
        assertEquals(15, e.column)
        assertTrue(e.reason.contains("decimal comma"), e.reason)
    }

    @Test
    fun `rows must have the header's field count`() {
        assertTrue(error("t_s,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,9.8,7\n").reason.contains("8 fields"))
        assertEquals(2, error("t_s,gx,gy,gz,ax,ay,az\n1,0,0\n").line)
    }

    @Test
    fun `non-finite times are errors, non-finite values are passed on`() {
        for (t in listOf("NaN", "Infinity", "-inf", "1e300")) {
            val e = error("t_s,gx,gy,gz,ax,ay,az\n$t,0,0,0,0,0,9.8\n")
            assertEquals(1, e.column, t)
            assertTrue(e.reason.contains("finite"), e.reason)
        }
        assertTrue(read("t_s,gx,gy,gz,ax,ay,az\n1,NaN,0,0,0,0,9.8\n")[0][1].isNaN())
    }

    @Test
    fun `a time that is not finite is the same error in an IMU table, on either row path, and in an orientation table`() {
        val plain = error("t_s,gx,gy,gz,ax,ay,az\n1e300,0,0,0,0,0,9.8\n") // a plain row: the one-pass parser
        val quoted = error("t_s,gx,gy,gz,ax,ay,az\n1e300,\"0\",0,0,0,0,9.8\n") // a quoted field: the general path
        val dir = kotlin.io.path.createTempDirectory("qtable")
        val table = dir.resolve("q.csv").also { it.toFile().writeText("t_s,qw,qx,qy,qz\n1e300,1,0,0,0\n") }
        val orientation = assertThrows<DataFormatException> { QuaternionTableReader.open(table).use { it.next() } }
        dir.toFile().deleteRecursively()
        assertEquals("column t_s: time '1e300' is not a finite time (or beyond ±292 years)", plain.reason)
        assertEquals(plain.reason, quoted.reason)
        assertEquals(plain.reason, orientation.reason)
        assertEquals(2L, orientation.line)
        assertEquals(1, orientation.column)
    }

    @Test
    fun `a long field is quoted as a short escaped excerpt`() {
        val e = error("t_s,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,${"x\u0001".repeat(5000)}\n")
        assertTrue(e.message!!.length < 200, e.message)
        assertTrue(e.message!!.contains("\\u0001"), e.message)
    }

    @Test
    fun `short rows, empty required fields and missing columns are errors`() {
        assertEquals(3, error("t_s,gx,gy,gz,ax,ay,az\n1,,0,0,0,0,9\n").column)
        assertTrue(error("t_s,gx,gy,gz,ax,ay\n").reason.contains("az"))
        assertTrue(error("t_s,gx,gy,gz,ax,ay,az,mx\n").reason.contains("mx,my,mz"))
        assertEquals(1, error("").line)
    }
}
