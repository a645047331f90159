package dev.motionfusion.core.input

import dev.motionfusion.core.io.DataFormatException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.ByteArrayInputStream
import java.nio.file.Path
import java.util.Random

/** The table parsed ahead on a second thread yields the same events, and its errors at the same row. */
class TableParseAheadTest {
    @TempDir
    lateinit var dir: Path

    private fun table(rows: Int, mag: Boolean, badRow: Int = -1): ByteArray {
        val r = Random(rows.toLong())
        val sb = StringBuilder(if (mag) "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" else "t_s,gx,gy,gz,ax,ay,az\n")
        for (i in 0 until rows) {
            sb.append(i * 0.005)
            repeat(if (mag) 9 else 6) { sb.append(',').append(if (i == badRow && it == 3) "1,5" else r.nextGaussian().toString()) }
            sb.append('\n')
        }
        return sb.toString().toByteArray()
    }

    private fun events(bytes: ByteArray, ahead: Boolean): List<String> {
        val out = ArrayList<String>()
        ImuTableEvents(ImuTableReader.open(ByteArrayInputStream(bytes), "t.csv"), ahead).use { e ->
            while (e.next()) out += "${e.stream} ${e.timestampNs} ${e.values.joinToString()}"
        }
        return out
    }

    @Test
    fun `the same events in the same order`() {
        for (rows in listOf(0, 1, 4095, 4096, 4097, 20_000)) {
            for (mag in listOf(false, true)) {
                val t = table(rows, mag)
                val serial = events(t, false)
                assertEquals(rows * (if (mag) 3 else 2), serial.size)
                assertEquals(serial, events(t, true), "$rows rows")
            }
        }
    }

    @Test
    fun `an error comes after the rows before it, with the same position`() {
        val t = table(10_000, true, badRow = 9_000)
        fun run(ahead: Boolean): Pair<Int, DataFormatException> {
            var n = 0
            val e = assertThrows(DataFormatException::class.java) {
                ImuTableEvents(ImuTableReader.open(ByteArrayInputStream(t), "t.csv"), ahead).use { ev -> while (ev.next()) n++ }
            }
            return n to e
        }
        val (serialEvents, serialError) = run(false)
        val (aheadEvents, aheadError) = run(true)
        assertEquals(9_000 * 3, serialEvents)
        assertEquals(serialEvents, aheadEvents)
        assertEquals(serialError.message, aheadError.message)
    }

    @Test
    fun `closing early stops the reader`() {
        val t = table(50_000, true)
        repeat(20) {
            ImuTableEvents(ImuTableReader.open(ByteArrayInputStream(t), "t.csv"), true).use { e -> repeat(it * 100) { e.next() } }
        }
        assertEquals(0, Thread.getAllStackTraces().keys.count { it.name == "table-reader" && it.isAlive })
    }
}
