package dev.motionfusion.app.build

import com.sun.net.httpserver.HttpServer
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.net.InetAddress
import java.net.InetSocketAddress
import java.security.MessageDigest
import java.util.zip.ZipEntry
import java.util.zip.ZipOutputStream

/**
 * The project's gradlew (a script in place of the wrapper jar) run against a fake distribution served
 * from this test: a zip whose bin/gradle prints its arguments. It runs the distribution whose
 * SHA-256 is distributionSha256Sum, refuses any other and leaves nothing behind, and never reuses a
 * download cut short or an unpacked folder without its completion marker.
 */
class GradleWrapperScriptTest {
    @TempDir
    lateinit var dir: File

    private var server: HttpServer? = null

    @AfterEach
    fun stop() { server?.stop(0) }

    private val userHome get() = File(dir, "gradle-home")
    private val dists get() = File(userHome, "wrapper/dists/gradle-0.1-bin")

    private fun distribution(echo: String): ByteArray {
        val out = java.io.ByteArrayOutputStream()
        ZipOutputStream(out).use { z ->
            z.putNextEntry(ZipEntry("gradle-0.1/bin/gradle"))
            z.write("#!/bin/sh\nfor a in \"\$@\"; do echo \"$echo:\$a\"; done\n".toByteArray())
            z.closeEntry()
        }
        return out.toByteArray()
    }

    private fun sha256(b: ByteArray) = MessageDigest.getInstance("SHA-256").digest(b).joinToString("") { "%02x".format(it) }

    /** Serves [body] at /gradle-0.1-bin.zip; with [cut], announces the full length but sends only half and closes. */
    private fun serve(body: ByteArray, cut: Boolean = false): String {
        server?.stop(0)
        val s = HttpServer.create(InetSocketAddress(InetAddress.getLoopbackAddress(), 0), 0)
        s.createContext("/gradle-0.1-bin.zip") { x ->
            x.sendResponseHeaders(200, body.size.toLong())
            x.responseBody.write(body, 0, if (cut) body.size / 2 else body.size)
            x.responseBody.flush()
            x.close()
        }
        s.start()
        server = s
        return "http\\://127.0.0.1:${s.address.port}/gradle-0.1-bin.zip"
    }

    private fun project(url: String, sum: String): File {
        val p = File(dir, "project")
        File(p, "gradle/wrapper").mkdirs()
        File(BuildFiles.repositoryRoot, "gradlew").copyTo(File(p, "gradlew"), overwrite = true)
        File(p, "gradle/wrapper/gradle-wrapper.properties").writeText("distributionUrl=$url\ndistributionSha256Sum=$sum\n")
        return p
    }

    private fun run(p: File, vararg args: String): Pair<Int, String> {
        val pb = ProcessBuilder(listOf("sh", File(p, "gradlew").path) + args).redirectErrorStream(true)
        pb.environment()["GRADLE_USER_HOME"] = userHome.path
        val proc = pb.start()
        val out = proc.inputStream.bufferedReader().readText()
        return proc.waitFor() to out
    }

    private fun leftovers(): List<String> = if (!dists.exists()) emptyList() else dists.walk().filter { it != dists }.map { it.relativeTo(dists).path }.toList()

    @Test
    fun `the distribution with the right checksum runs with the arguments given`() {
        val zip = distribution("fresh")
        val p = project(serve(zip), sha256(zip))
        val (code, out) = run(p, "assembleDebug", "two words")
        assertEquals(0, code, out)
        assertTrue(out.contains("fresh:assembleDebug\nfresh:two words\n"), out)
        // A second run does not download again.
        server!!.stop(0)
        val (again, out2) = run(p, "x")
        assertEquals(0, again, out2)
        assertTrue(out2.contains("fresh:x") && !out2.contains("Downloading"), out2)
    }

    @Test
    fun `a distribution with another checksum is refused and leaves nothing behind`() {
        val zip = distribution("evil")
        val p = project(serve(zip), sha256(distribution("good")))
        val (code, out) = run(p, "tasks")
        assertNotEquals(0, code)
        assertTrue(out.contains("not distributionSha256Sum") && !out.contains("evil:"), out)
        assertEquals(emptyList<String>(), leftovers())
    }

    @Test
    fun `a download cut short is not reused`() {
        val zip = distribution("fresh")
        val p = project(serve(zip, cut = true), sha256(zip))
        val (code, out) = run(p, "tasks")
        assertNotEquals(0, code, out)
        assertEquals(emptyList<String>(), leftovers())
        project(serve(zip), sha256(zip))
        val (again, out2) = run(p, "tasks")
        assertEquals(0, again, out2)
        assertTrue(out2.contains("fresh:tasks"), out2)
    }

    @Test
    fun `an unpacked folder without its completion marker is replaced`() {
        val zip = distribution("fresh")
        val p = project(serve(zip), sha256(zip))
        // What an unzip stopped half-way leaves: the launcher, no marker.
        val half = File(dists, "script-${sha256(zip)}/gradle-0.1/bin/gradle")
        half.parentFile.mkdirs()
        half.writeText("#!/bin/sh\necho stale\n")
        val (code, out) = run(p, "tasks")
        assertEquals(0, code, out)
        assertTrue(out.contains("fresh:tasks") && !out.contains("stale"), out)
    }
}
