package dev.motionfusion.core.io

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.io.ByteArrayOutputStream
import java.util.zip.GZIPOutputStream

class ImuTableReaderTest {

    private fun read(text: String): List<ImuSample> = read(text.toByteArray())

    private fun read(bytes: ByteArray): List<ImuSample> =
        ImuTableReader.open(bytes.inputStream(), "t.csv").use { it.asSequence().toList() }

    private fun error(text: String): DataFormatException =
        assertThrows { read(text) }

    @Test
    fun `reads every column in SI units`() {
        val rows = read("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n0.5,0.1,0.2,0.3,1,2,9.81,20,-5,-40\n0.51,1e-3,-2E-2,0,0,0,0,NaN,1,2\n")
        assertEquals(2, rows.size)
        assertEquals(ImuSample(0.5, 0.1, 0.2, 0.3, 1.0, 2.0, 9.81, 20.0, -5.0, -40.0), rows[0])
        assertEquals(-0.02, rows[1].gy)
        assertTrue(rows[1].mx.isNaN())
    }

    @Test
    fun `finds columns by name in any order and without magnetometer`() {
        ImuTableReader.open("az,ay,ax,gz,gy,gx,t_s,extra\r\n9,8,7,3,2,1,0.25,x\r\n".byteInputStream(), "t.csv").use { r ->
            assertFalse(r.hasMagnetometer)
            val s = r.next()
            assertEquals(ImuSample(0.25, 1.0, 2.0, 3.0, 7.0, 8.0, 9.0, Double.NaN, Double.NaN, Double.NaN), s)
            assertFalse(r.hasNext())
        }
    }

    @Test
    fun `gzip is detected by content`() {
        val bos = ByteArrayOutputStream()
        GZIPOutputStream(bos).use { it.write("t_s,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,9.8\n".toByteArray()) }
        assertEquals(1.0, read(bos.toByteArray()).single().timeS)
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
        for (bad in listOf("1,5", "0x1p3", "1.0f", "2d")) {
            val e = error("t_s,gx,gy,gz,ax,ay,az\n\"$bad\",0,0,0,0,0,9.8\n")
            assertEquals(2, e.line, bad)
        }
    }

    @Test
    fun `short rows, empty required fields and missing columns are errors`() {
        assertEquals(2, error("t_s,gx,gy,gz,ax,ay,az\n1,0,0\n").line)
        assertEquals(3, error("t_s,gx,gy,gz,ax,ay,az\n1,,0,0,0,0,9\n").column)
        assertTrue(error("t_s,gx,gy,gz,ax,ay\n").reason.contains("az"))
        assertTrue(error("t_s,gx,gy,gz,ax,ay,az,mx\n").reason.contains("mx,my,mz"))
        assertEquals(1, error("").line)
    }
}
