package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.zip.GZIPOutputStream

class CliTest {
    @TempDir
    lateinit var dir: Path


    private fun table(name: String, text: String, gzip: Boolean = false): String {
        val p = dir.resolve(name)
        if (gzip) GZIPOutputStream(Files.newOutputStream(p)).use { it.write(text.toByteArray()) } else Files.writeString(p, text)
        return p.toString()
    }

    @Test
    fun `help lists commands and exit codes`() {
        val r = fusion("--help")
        assertEquals(ExitCode.OK, r.code)
        assertTrue(r.out.contains("summary"), r.out)
        assertTrue(r.out.contains("Exit codes"), r.out)
        assertEquals(ExitCode.USAGE, fusion().code)
    }

    @Test
    fun `version comes from the build`() {
        val r = fusion("--version")
        assertEquals(ExitCode.OK, r.code)
        assertTrue(Regex("""fusion \d+\.\d+\.\d+\S*""").matches(r.out.trim()), r.out)
    }

    @Test
    fun `every command has its own help`() {
        val r = fusion("summary", "--help")
        assertEquals(ExitCode.OK, r.code)
        assertTrue(r.out.startsWith("Usage: fusion summary"), r.out)
        assertEquals(r.out, fusion("help", "summary").out)
    }

    @Test
    fun `summary of a gzip table with magnetometer`() {
        val rows = (0 until 101).joinToString("\n") { i ->
            "${i * 0.01},0.01,-0.02,0.03,0.1,0.2,9.8,20,0,-40"
        }
        val f = table("t.csv.gz", "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n$rows\n", gzip = true)
        val r = fusion("summary", f)
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(r.out.contains("samples     101"), r.out)
        assertTrue(r.out.contains("duration    1.000 s"), r.out)
        assertTrue(r.out.contains("rate        100.000 Hz"), r.out)
        assertTrue(Regex("""gz\s+0\.030000 rad/s""").containsMatchIn(r.out), r.out)
        assertTrue(Regex("""mz\s+-40\.000000 µT""").containsMatchIn(r.out), r.out)
        assertTrue(r.out.contains("0 backwards, 0 repeated"), r.out)
    }

    @Test
    fun `summary of a table paused for a minute, one in reverse and one with a header only`() {
        // 100 Hz for 3 s, 60 s of nothing, 3 s more: the phone's rate, and the pause named.
        val paused = (0 until 600).joinToString("\n") { i -> "${i * 0.01 + if (i >= 300) 60.0 else 0.0},0,0,0,0,0,9.8" }
        val r = fusion("summary", table("paused.csv", "t_s,gx,gy,gz,ax,ay,az\n$paused\n"))
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(r.out.contains("rate        100.000 Hz"), r.out)
        assertTrue(r.out.contains("gaps        1, the longest 60.010 s (left out of the rate)"), r.out)
        val reversed = (100 downTo 0).joinToString("\n") { i -> "${i * 0.01},0,0,0,0,0,9.8" }
        val back = fusion("summary", table("reversed.csv", "t_s,gx,gy,gz,ax,ay,az\n$reversed\n"))
        assertEquals(ExitCode.OK, back.code, back.err)
        assertTrue(back.out.contains("(times span 1.000 s: rows out of order)") && back.out.contains("100 backwards"), back.out)
        val empty = fusion("summary", table("header.csv", "t_s,gx,gy,gz,ax,ay,az\n"))
        assertEquals(ExitCode.DATA_ERROR, empty.code, empty.out)
        assertTrue("no rows after the header" in empty.err, empty.err)
    }

    @Test
    fun `summary counts timestamps that go back or repeat`() {
        val f = table("t.csv", "t_s,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9.8\n1,0,0,0,0,0,9.8\n1,0,0,0,0,0,9.8\n0.5,0,0,0,0,0,9.8\n")
        val r = fusion("summary", f)
        assertTrue(r.out.contains("1 backwards, 1 repeated"), r.out)
        assertTrue(r.out.contains("(no magnetometer columns)"), r.out)
    }

    @Test
    fun `malformed input names file line and column with exit code 1`() {
        val f = table("bad.csv", "t_s,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9.8\n0.01,0,zz,0,0,0,9.8\n")
        val r = fusion("summary", f)
        assertEquals(ExitCode.DATA_ERROR, r.code)
        assertEquals("fusion: $f:3:8: column gy: 'zz' is not a number", r.err.trim())
    }

    @Test
    fun `usage and io errors have their own exit codes`() {
        assertEquals(ExitCode.USAGE, fusion("nope").code)
        assertEquals(ExitCode.USAGE, fusion("summary").code)
        assertEquals(ExitCode.USAGE, fusion("summary", "--frobnicate").code)
        val missing = fusion("summary", dir.resolve("missing.csv").toString())
        assertEquals(ExitCode.IO_ERROR, missing.code)
        assertTrue(missing.err.contains("missing.csv: no such file"), missing.err)
    }
}
