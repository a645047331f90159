package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path

/**
 * Runs of `fusion` as its own process, for what an in-process run cannot show: the file name
 * encoding the JVM takes from the locale at start-up, and the process's real standard input.
 */
class ProcessRunsTest {
    @TempDir
    lateinit var tmp: Path

    private class Run(val code: Int, val out: String, val err: String)

    private fun fusion(env: Map<String, String>, stdin: ByteArray, vararg args: String): Run {
        val java = Path.of(System.getProperty("java.home"), "bin", "java").toString()
        val pb = ProcessBuilder(listOf(java, "-cp", System.getProperty("java.class.path"), "dev.motionfusion.cli.MainKt") + args)
            .directory(tmp.toFile())
        pb.environment().putAll(env)
        val out = tmp.resolve("out.txt")
        val err = tmp.resolve("err.txt")
        pb.redirectOutput(out.toFile()).redirectError(err.toFile())
        val p = pb.start()
        p.outputStream.use { it.write(stdin) }
        p.waitFor()
        return Run(p.exitValue(), Files.readString(out, Charsets.ISO_8859_1), Files.readString(err, Charsets.ISO_8859_1))
    }

    private fun table(name: String): Path {
        val f = tmp.resolve(name)
        check(fusion("simulate", "-o", f.toString(), "--duration", "5", "--rate", "50").code == 0)
        return f
    }

    @Test
    fun `a file name that the C locale cannot represent is a usage error, not an internal one`() {
        table("é.csv")
        val r = fusion(mapOf("LANG" to "C", "LC_ALL" to "C"), ByteArray(0), "summary", "é.csv")
        assertEquals(ExitCode.USAGE, r.code, r.err)
        assertTrue(r.err.contains("cannot be represented in the system's file name encoding") && r.err.contains("LC_ALL=C.UTF-8"), r.err)
        assertTrue(!r.err.contains("internal error") && !r.err.contains("Exception"), r.err)
    }

    @Test
    fun `dev stdin and - read the process's standard input`() {
        val bytes = Files.readAllBytes(table("t.csv"))
        for (name in listOf("/dev/stdin", "-")) {
            val r = fusion(emptyMap(), bytes, "summary", name)
            assertEquals(ExitCode.OK, r.code, r.err)
            assertTrue(r.out.contains("samples     250"), r.out)
            val replay = fusion(emptyMap(), bytes, "replay", name)
            assertEquals(ExitCode.OK, replay.code, replay.err)
            assertEquals(251, replay.out.trim().lines().size, "a header and 250 rows")
        }
    }
}
