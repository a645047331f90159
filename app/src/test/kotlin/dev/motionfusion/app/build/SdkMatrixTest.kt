package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.platform.Sdks
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.util.Properties

/**
 * The version matrix covers exactly the versions the app supports, and each one can run offline:
 * [Sdks] spans the app's minSdk to targetSdk (to `android.testMaxSdk` while Robolectric cannot run the
 * targetSdk on the build's JDK), the root pom names a Robolectric framework jar for
 * every level in it, the app's build copies each of them where Robolectric looks, and the tests
 * that are not version-dependent run at the newest.
 */
class SdkMatrixTest {
    private val root = BuildFiles.repositoryRoot
    private val appPom = BuildFiles.parse(File(root, "app/pom.xml"))
    private val rootPom = BuildFiles.parse(File(root, "pom.xml"))

    private fun props(pom: org.w3c.dom.Element) =
        pom.child("properties")!!.children().associate { it.tagName to it.textContent.trim() }

    @Test
    fun `the matrix spans minSdk to targetSdk`() {
        val app = props(appPom)
        assertEquals(app.getValue("android.minSdk").toInt(), Sdks.MIN, "Sdks.MIN is the app's minSdk")
        // The newest level Robolectric runs here (android.testMaxSdk), the targetSdk itself unless that is newer.
        val target = app.getValue("android.targetSdk").toInt()
        val testMax = app.getValue("android.testMaxSdk").toInt()
        assertTrue(testMax <= target, "android.testMaxSdk $testMax above targetSdk $target")
        assertEquals(minOf(target, testMax), Sdks.MAX, "Sdks.MAX is the app's targetSdk, or the newest level the tests can run")
    }

    @Test
    fun `every level has its framework jar, copied for the tests`() {
        val versions = props(rootPom)
        val copied = appPom.child("build")!!.child("plugins")!!.children("plugin")
            .flatMap { it.child("executions")?.children("execution").orEmpty() }
            .single { it.child("id")?.textContent == "robolectric-android-all" }
            .child("configuration")!!.child("artifactItems")!!.children("artifactItem")
            .map { it.child("version")!!.textContent.trim() }
        val deps = File(System.getProperty("robolectric.dependency.dir") ?: error("robolectric.dependency.dir not set"))
        for (level in Sdks.MIN..Sdks.MAX) {
            val key = "android.all.instrumented.$level"
            val version = versions[key] ?: error("root pom.xml has no <$key>: API $level would not run offline")
            assertTrue("\${$key}" in copied, "app/pom.xml does not copy $key")
            val jar = File(deps, "android-all-instrumented-$version.jar")
            assertTrue(jar.isFile, "$jar missing: Robolectric cannot start API $level offline")
        }
        val extra = versions.keys.filter { it.startsWith("android.all.instrumented.") }
            .map { it.substringAfterLast('.').toInt() }.filter { it !in Sdks.MIN..Sdks.MAX }
        assertEquals(emptyList<Int>(), extra, "framework jars for levels the app does not support")
    }

    @Test
    fun `tests that do not depend on the version run at the newest`() {
        val p = Properties().apply { File(root, "app/src/test/resources/robolectric.properties").reader().use(::load) }
        assertEquals(Sdks.MAX.toString(), p.getProperty("sdk"))
    }
}
