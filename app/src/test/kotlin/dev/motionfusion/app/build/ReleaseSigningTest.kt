package dev.motionfusion.app.build

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File

/** A release build is never signed with the debug key, nor without a key: tools/android-build.sh stops first. */
class ReleaseSigningTest {
    @TempDir
    lateinit var target: File

    private fun releaseApk(keystore: String, password: String, alias: String): Pair<Int, String> {
        val script = File(BuildFiles.repositoryRoot, "tools/android-build.sh")
        val p = ProcessBuilder("bash", script.path, "apk", "release", "android.jar", "r8.jar", target.path, "rules.pro", keystore, password, alias)
            .redirectErrorStream(true).start()
        val out = p.inputStream.bufferedReader().readText()
        return p.waitFor() to out
    }

    @Test
    fun `without a key the release build stops and says how to give one`() {
        val (code, out) = releaseApk("", "", "")
        assertNotEquals(0, code)
        assertTrue(out.contains("a release build needs a signing key: mvn -Prelease package -Drelease.keystore=FILE"), out)
    }

    @Test
    fun `the debug key is refused for a release build`() {
        val debugKey = File(BuildFiles.repositoryRoot, "app/debug.keystore").path
        val (code, out) = releaseApk(debugKey, "android", "androiddebugkey")
        assertNotEquals(0, code)
        assertTrue(out.contains("the debug key signs debug builds only"), out)
        assertEquals(emptyList<String>(), target.list()!!.toList(), "nothing built")
    }
}
