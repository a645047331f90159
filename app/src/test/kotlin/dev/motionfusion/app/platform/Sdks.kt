package dev.motionfusion.app.platform

/**
 * The Android versions the app's version-dependent tests run on: every API level from the app's
 * minSdk to its targetSdk (app/pom.xml) as far as Robolectric runs here (`android.testMaxSdk`: API 36 needs
 * Java 21), each with its own Robolectric framework jar. A test whose
 * behaviour depends on the version takes `@Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)` (or a part
 * of that range where the behaviour exists only there); every other test runs at the newest level
 * (src/test/resources/robolectric.properties). SdkMatrixTest checks these against the build.
 */
object Sdks {
    const val MIN = 26
    const val MAX = 35
}
